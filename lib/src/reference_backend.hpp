// The CPU reference: the shared filter code (kernels/pnf_filter.h) in double, on OpenMP threads.
#pragma once

#include <memory>

#include "filter_backend.hpp"

namespace pnf::detail {

// threads: OpenMP threads, 0 for all cores.
std::unique_ptr<FilterBackend> make_reference_backend(int threads);

}  // namespace pnf::detail
