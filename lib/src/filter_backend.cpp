#include "filter_backend.hpp"

#include "opencl_backend.hpp"
#include "reference_backend.hpp"

namespace pnf::detail {

std::unique_ptr<FilterBackend> make_backend(const FilterOptions& options, int lanes) {
  if (options.device.backend == Backend::opencl) return make_opencl_backend(options.device.selector, lanes);
  return make_reference_backend(options.reference_threads);
}

}  // namespace pnf::detail
