#include "pnf/normal_filter.hpp"

#include <cmath>

#include "filter_engine.hpp"
#include "pnf/error.hpp"

namespace pnf {
namespace {

[[noreturn]] void bad_option(const std::string& field, const std::string& value, const std::string& rule) {
  throw Error(ErrorCode::invalid_argument, "invalid filter option " + field + " = " + value + ": " + rule);
}

}  // namespace

const char* to_string(RadiusSource source) {
  switch (source) {
    case RadiusSource::not_used: return "not used";
    case RadiusSource::given: return "given";
    case RadiusSource::property: return "radius property";
    case RadiusSource::estimate: return "estimated from neighbour distances";
  }
  return "unknown";
}

void MemoryPolicy::validate() const {
  if (budget_bytes == 0) bad_option("memory.budget_bytes", "0", "must be > 0");
  if (max_neighbour_pairs == 0) bad_option("memory.max_neighbour_pairs", "0", "must be > 0");
}

void FilterOptions::validate() const {
  if (device.backend != Backend::opencl && device.backend != Backend::reference) {
    bad_option("device.backend", std::to_string(int(device.backend)), "must be opencl or reference");
  }
  memory.validate();
  if (!(std::isfinite(max_seconds) && max_seconds >= 0)) {
    bad_option("max_seconds", std::to_string(max_seconds), "must be >= 0 and finite (0: no limit)");
  }
  if (reference_threads < 0) {
    bad_option("reference_threads", std::to_string(reference_threads), "must be >= 0 (0: all cores)");
  }
}

struct NormalFilter::Impl {
  FilterOptions options;
  std::unique_ptr<detail::FilterBackend> backend;
};


FilterSummary NormalFilter::run_observed(const CloudView& cloud, MutableVec3ArrayView normals_out,
                                         const FilterParams& params, const PassObserver& observe,
                                         const ProgressCallback& progress) {
  // A distributed part that owns every point: its halo exchange, called after each pass with the
  // new normals and with no halo to fill, is the observer.
  int pass = 0;
  bool go_on = true;
  detail::DistributedPart whole;
  whole.owned = cloud.size();
  whole.exchange_halo = [&](const std::vector<double>& normals, std::vector<double>&) {
    go_on = !observe || observe(++pass, normals);
  };
  whole.ends_passes = [&] { return !go_on; };
  whole.one_process = true;
  return detail::run_filter(*impl_->backend, impl_->options, cloud, normals_out, params, progress, &whole);
}

NormalFilter::NormalFilter(const FilterOptions& options) : impl_(std::make_unique<Impl>()) {
  options.validate();
  impl_->options = options;
  impl_->options.device = options.device.resolved();
  impl_->backend = detail::make_backend(impl_->options);
}
NormalFilter::~NormalFilter() = default;
NormalFilter::NormalFilter(NormalFilter&&) noexcept = default;
NormalFilter& NormalFilter::operator=(NormalFilter&&) noexcept = default;

std::string NormalFilter::device_description() const { return impl_->backend->description(); }

FilterSummary NormalFilter::run(const CloudView& cloud, MutableVec3ArrayView normals_out, const FilterParams& params,
                                const ProgressCallback& progress) {
  return detail::run_filter(*impl_->backend, impl_->options, cloud, normals_out, params, progress);
}

FilterResult NormalFilter::run(const PointCloud& cloud, const FilterParams& params, const ProgressCallback& progress) {
  FilterResult result;
  result.normals.resize(cloud.size());
  result.summary = run(CloudView(cloud), MutableVec3ArrayView(result.normals), params, progress);
  return result;
}

}  // namespace pnf
