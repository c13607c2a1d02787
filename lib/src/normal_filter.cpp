#include "pnf/normal_filter.hpp"

#include "filter_engine.hpp"
#include "opencl_backend.hpp"
#include "pnf/error.hpp"
#include "reference_backend.hpp"

namespace pnf {

const char* to_string(Backend backend) { return backend == Backend::opencl ? "opencl" : "reference"; }

const char* to_string(RadiusSource source) {
  switch (source) {
    case RadiusSource::not_used: return "not used";
    case RadiusSource::given: return "given";
    case RadiusSource::property: return "radius property";
    case RadiusSource::estimate: return "estimated from neighbour distances";
  }
  return "unknown";
}

struct NormalFilter::Impl {
  FilterOptions options;
  std::unique_ptr<detail::FilterBackend> backend;
};

NormalFilter::NormalFilter(const FilterOptions& options) : impl_(std::make_unique<Impl>()) {
  if (options.memory_budget_bytes == 0) {
    throw Error(ErrorCode::invalid_argument, "invalid filter option memory_budget_bytes = 0: must be > 0");
  }
  if (options.threads < 0) {
    throw Error(ErrorCode::invalid_argument,
                "invalid filter option threads = " + std::to_string(options.threads) + ": must be >= 0 (0: all cores)");
  }
  if (options.lanes != 0 && options.lanes != 1 && options.lanes != 4 && options.lanes != 8 && options.lanes != 16) {
    throw Error(ErrorCode::invalid_argument,
                "invalid filter option lanes = " + std::to_string(options.lanes) + ": must be 0 (auto), 1, 4, 8 or 16");
  }
  impl_->options = options;
  impl_->backend = options.backend == Backend::opencl ? detail::make_opencl_backend(options.device, options.lanes)
                                                      : detail::make_reference_backend(options.threads);
}

NormalFilter::~NormalFilter() = default;
NormalFilter::NormalFilter(NormalFilter&&) noexcept = default;
NormalFilter& NormalFilter::operator=(NormalFilter&&) noexcept = default;

std::string NormalFilter::device_description() const { return impl_->backend->description(); }

FilterResult NormalFilter::run(const PointCloud& cloud, const FilterParams& params, const ProgressCallback& progress) {
  return detail::run_filter(*impl_->backend, impl_->options, cloud, params, progress);
}

FilterResult improve_normals(const PointCloud& cloud, const FilterParams& params, const FilterOptions& options) {
  return NormalFilter(options).run(cloud, params);
}

}  // namespace pnf
