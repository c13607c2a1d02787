// The OpenCL backend: kernels/filter.cl in float32 on one device.
#pragma once

#include <memory>
#include <string>

#include "filter_backend.hpp"

namespace pnf::detail {

// Picks the device (see ClRuntime) and builds the kernels once. Throws pnf::Error(device).
// lanes: PNF_LANES for the kernel build, 0 for the device type's default.
std::unique_ptr<FilterBackend> make_opencl_backend(const std::string& selector, int lanes);

}  // namespace pnf::detail
