// The OpenCL backend: kernels/filter.cl in float32 on one device.
#pragma once

#include <memory>
#include <string>

#include "filter_backend.hpp"

namespace pnf::detail {

// Picks the device (see ClRuntime) and builds the kernels once. Throws pnf::Error(device).
// lanes: PNF_LANES for the kernel build (1, 4, 8 or 16), 0 for the device type's default.
// extra_options: appended to the program's build options; for measurements only (the bench's
// --kernel-options, e.g. "-DPNF_WEIGHT_CUT_EXPONENT=-1e30" to time the kernel without its cut).
std::unique_ptr<FilterBackend> make_opencl_backend(const std::string& selector, int lanes,
                                                   const std::string& extra_options = "");

}  // namespace pnf::detail
