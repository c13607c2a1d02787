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

namespace {

// A distributed part that owns every point: its halo exchange, called after each pass with the
// new normals and with no halo to fill, is the observer.
class ObservedPart {
 public:
  ObservedPart(std::size_t points, const NormalFilter::PassObserver& observe) {
    part_.owned = points;
    part_.exchange_halo = [this, &observe](const std::vector<double>& normals, std::vector<double>&) {
      go_on_ = !observe || observe(++pass_, normals);
    };
    part_.ends_passes = [this] { return !go_on_; };
    part_.one_process = true;
  }
  ObservedPart(const ObservedPart&) = delete;
  ObservedPart& operator=(const ObservedPart&) = delete;
  const detail::DistributedPart* get() const { return &part_; }

 private:
  detail::DistributedPart part_;
  int pass_ = 0;
  bool go_on_ = true;
};

}  // namespace

FilterSummary NormalFilter::run_observed(const CloudView& cloud, MutableVec3ArrayView normals_out,
                                         const FilterParams& params, const PassObserver& observe,
                                         const ProgressCallback& progress) {
  ObservedPart whole(cloud.size(), observe);  // not const: its observer counts the passes
  return detail::run_filter(*impl_->backend, impl_->options, cloud, normals_out, params, progress, whole.get());
}

FilterSummary NormalFilter::run_observed_after_twin(const CloudView& cloud, const Vec3ArrayView& twin_normals,
                                                    const PassObserver& observe_twin, MutableVec3ArrayView normals_out,
                                                    const FilterParams& params, const PassObserver& observe,
                                                    const ProgressCallback& progress) {
  ObservedPart whole(cloud.size(), observe), twin_whole(cloud.size(), observe_twin);
  const detail::TwinRun twin{twin_normals, twin_whole.get()};
  return detail::run_filter(*impl_->backend, impl_->options, cloud, normals_out, params, progress, whole.get(), &twin);
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
