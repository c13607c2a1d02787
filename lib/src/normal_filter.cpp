#include "pnf/normal_filter.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "chunk_plan.hpp"
#include "cloud_checks.hpp"
#include "filter_backend.hpp"
#include "mean_radius_internal.hpp"
#include "neighbour_lists.hpp"
#include "opencl_backend.hpp"
#include "pnf/error.hpp"
#include "pnf_filter.h"
#include "reference_backend.hpp"
#include "spatial_order.hpp"

namespace pnf {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The cloud in the order and frame the backends see: along the Morton curve, re-centred on the
// bounding-box centre in double before anything becomes float (SPEC, "Numerics").
struct OrderedCloud {
  std::vector<std::uint32_t> order;  // order[k] = input index of point k
  std::vector<double> positions;     // N by 3
  std::vector<double> normals;       // N by 3, unit
};

OrderedCloud order_cloud(const PointCloud& cloud, const std::vector<Vec3>& unit) {
  OrderedCloud out;
  out.order = detail::morton_order(cloud.positions);
  Vec3 lo = cloud.positions[0], hi = cloud.positions[0];
  for (const Vec3& p : cloud.positions) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  }
  const Vec3 centre = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
  const std::size_t n = cloud.size();
  out.positions.resize(3 * n);
  out.normals.resize(3 * n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = out.order[k];
    for (int c = 0; c < 3; ++c) {
      out.positions[3 * k + c] = cloud.positions[i][c] - centre[c];
      out.normals[3 * k + c] = unit[i][c];
    }
  }
  return out;
}

double resolve_mean_radius(const PointCloud& cloud, const FilterParams& params, const detail::NeighbourSearch& search,
                           RadiusSource& source) {
  if (params.units == Units::absolute) {
    source = RadiusSource::not_used;
    return 0;
  }
  if (params.mean_radius > 0) {
    source = RadiusSource::given;
    return params.mean_radius;
  }
  if (cloud.has_radii()) {
    source = RadiusSource::property;
    return std::accumulate(cloud.radii.begin(), cloud.radii.end(), 0.0) / double(cloud.radii.size());
  }
  source = RadiusSource::estimate;
  double estimate = detail::estimate_mean_radius(search);
  if (!(estimate > 0)) {
    throw Error(ErrorCode::invalid_input,
                "cannot estimate the mean surfel radius of " + std::to_string(cloud.size()) +
                    " points (it needs at least 5 points, not most of them at one place); give the mean radius "
                    "explicitly or use absolute units");
  }
  return estimate;
}

}  // namespace

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
  params.validate();
  detail::check_cloud(cloud);
  detail::FilterBackend& backend = *impl_->backend;

  FilterResult result;
  FilterSummary& summary = result.summary;
  summary.points = cloud.size();
  summary.backend = to_string(impl_->options.backend);
  summary.device = backend.description();
  if (cloud.size() == 0) return result;

  const std::vector<Vec3> unit = detail::unit_normals(cloud.normals);
  auto start = Clock::now();
  OrderedCloud ordered = order_cloud(cloud, unit);
  detail::NeighbourSearch search(ordered.positions.data(), cloud.size());
  summary.mean_radius = resolve_mean_radius(cloud, params, search, summary.radius_source);
  const double scale = params.units == Units::radius ? summary.mean_radius : 1.0;
  summary.sigma_f = params.sigma_f * scale;
  summary.sigma_g = params.sigma_g * scale;
  const double reach = PNF_SUPPORT_IN_SIGMA_F * summary.sigma_f;
  // Counted before any list is allocated, so the memory is known first (SPEC, "Neighbour lists").
  const std::vector<std::uint32_t> counts = search.count_within(reach);
  summary.neighbour_pairs = std::accumulate(counts.begin(), counts.end(), std::size_t(0));
  summary.neighbours_mean = double(summary.neighbour_pairs) / double(cloud.size());
  summary.neighbours_max = *std::max_element(counts.begin(), counts.end());
  const std::vector<detail::Chunk> chunks =
      detail::plan_chunks(counts, impl_->options.memory_budget_bytes, backend.max_list_bytes());
  summary.chunks = chunks.size();
  summary.neighbour_seconds = seconds_since(start);

  if (params.iterations == 0) {
    result.normals = unit;
    return result;
  }

  const pnf_coeffs c = pnf_make_coeffs(summary.sigma_f, summary.sigma_g);
  const detail::Coefficients coefficients{c.inv_two_sigma_f2, c.inv_two_sigma_g2};
  start = Clock::now();
  backend.upload_cloud(ordered.positions, ordered.normals);
  summary.upload_seconds = seconds_since(start);

  auto load_chunk = [&](const detail::Chunk& chunk) {
    auto t = Clock::now();
    std::size_t pairs = 0;
    for (std::size_t i = chunk.first; i < chunk.first + chunk.count; ++i) pairs += counts[i];
    detail::ListStorage storage = backend.begin_lists(chunk.first, chunk.count, pairs);
    summary.upload_seconds += seconds_since(t);
    t = Clock::now();
    search.fill_lists(reach, chunk.first, chunk.count, counts, storage.offsets, storage.indices);
    summary.neighbour_seconds += seconds_since(t);
    t = Clock::now();
    backend.end_lists();
    summary.upload_seconds += seconds_since(t);
  };
  const bool whole = chunks.size() == 1;
  if (whole) load_chunk(chunks[0]);  // built once, kept on the device for every pass

  for (int pass = 1; pass <= params.iterations; ++pass) {
    auto pass_start = Clock::now();
    for (const detail::Chunk& chunk : chunks) {
      if (!whole) load_chunk(chunk);
      backend.run_chunk(coefficients);
    }
    summary.kernel_seconds.push_back(backend.end_pass());
    summary.pass_seconds.push_back(seconds_since(pass_start));
    if (progress && !progress(PassProgress{pass, params.iterations, summary.pass_seconds.back()})) {
      throw Error(ErrorCode::cancelled, "cancelled by the progress callback after pass " + std::to_string(pass));
    }
  }

  summary.device_bytes = backend.device_bytes();
  const std::vector<double> out = backend.download_normals();
  result.normals.resize(cloud.size());
  for (std::size_t k = 0; k < cloud.size(); ++k) {
    // Re-normalised in double: float32 unit vectors are unit only to about 1e-7.
    Vec3 n = {out[3 * k], out[3 * k + 1], out[3 * k + 2]};
    double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    result.normals[ordered.order[k]] = {n[0] / len, n[1] / len, n[2] / len};
  }
  return result;
}

FilterResult improve_normals(const PointCloud& cloud, const FilterParams& params, const FilterOptions& options) {
  return NormalFilter(options).run(cloud, params);
}

}  // namespace pnf
