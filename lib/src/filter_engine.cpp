#include "filter_engine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <utility>

#include "chunk_plan.hpp"
#include "cloud_checks.hpp"
#include "geometry.hpp"
#include "mean_radius_internal.hpp"
#include "pnf/bounding_box.hpp"
#include "pnf/error.hpp"
#include "pnf_filter.h"
#include "spatial/spatial_index.hpp"
#include "spatial/spatial_order.hpp"

namespace pnf::detail {
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

OrderedCloud order_cloud(const PointCloud& cloud, const std::vector<double>& unit) {
  OrderedCloud out;
  out.order = morton_order(cloud.positions);
  const Vec3 centre = bounding_box(cloud.positions).centre();
  const std::size_t n = cloud.size();
  out.positions.resize(3 * n);
  out.normals.resize(3 * n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = out.order[k];
    for (int c = 0; c < 3; ++c) {
      out.positions[3 * k + c] = cloud.positions[i][c] - centre[c];
      out.normals[3 * k + c] = unit[3 * i + c];
    }
  }
  return out;
}

double resolve_mean_radius(const PointCloud& cloud, const FilterParams& params, const SpatialIndex& search,
                           RadiusSource& source) {
  if (params.units == Units::absolute) {
    source = RadiusSource::not_used;
    return 0;
  }
  const MeanRadius radius = detail::resolve_mean_radius(params.mean_radius, cloud.radii, cloud.size(),
                                                        [&] { return estimate_mean_radius(search); });
  source = radius.source;
  return radius.value;
}

// Mean angle in degrees between two N by 3 arrays of unit vectors (atan2: exact near 0).
double mean_angle_deg(const std::vector<double>& a, const std::vector<double>& b) {
  double sum = 0;
  const std::size_t n = a.size() / 3;
  for (std::size_t i = 0; i < n; ++i) {
    sum += geometry::angle_radians({a[3 * i], a[3 * i + 1], a[3 * i + 2]}, {b[3 * i], b[3 * i + 1], b[3 * i + 2]});
  }
  return n > 0 ? sum / double(n) * 180.0 / geometry::kPi : 0.0;
}

std::string gib(double bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f GiB", bytes / double(std::size_t(1) << 30));
  return text;
}

// Refuses, before the exact count, a neighbourhood so wide that the lists would pass
// options.max_neighbour_pairs (every point neighbouring every other, say): that count alone
// would take hours. A sample of points gives the estimate.
void check_pair_estimate(const SpatialIndex& search, double reach, const FilterOptions& options,
                         const FilterSummary& summary) {
  const double estimate = search.estimate_pairs(reach);
  if (estimate <= double(options.max_neighbour_pairs)) return;
  const double per_point = estimate / double(search.size());
  throw Error(ErrorCode::invalid_argument,
              "sigma_f = " + std::to_string(summary.sigma_f) + " model units gives about " +
                  std::to_string(std::llround(per_point)) + " neighbours per point, about " +
                  std::to_string(std::llround(estimate)) + " neighbour pairs (" + gib(estimate * 4) +
                  " of lists, as many kernel evaluations per pass), more than the limit of " +
                  std::to_string(options.max_neighbour_pairs) +
                  " pairs; lower sigma_f, or raise FilterOptions::max_neighbour_pairs");
}

}  // namespace

FilterResult run_filter(FilterBackend& backend, const FilterOptions& options, const PointCloud& cloud,
                        const FilterParams& params, const ProgressCallback& progress) {
  params.validate();
  check_cloud(cloud, CloudRequirements::filter());

  FilterResult result;
  FilterSummary& summary = result.summary;
  summary.points = cloud.size();
  summary.backend = to_string(options.backend);
  summary.device = backend.description();
  if (cloud.size() == 0) return result;

  const std::vector<double> unit = unit_normals(cloud.normals);
  auto start = Clock::now();
  OrderedCloud ordered = order_cloud(cloud, unit);
  const SpatialIndex search(std::move(ordered.positions));  // no copy: the tree searches them in place
  summary.mean_radius = resolve_mean_radius(cloud, params, search, summary.radius_source);
  const double scale = params.units == Units::radius ? summary.mean_radius : 1.0;
  summary.sigma_f = params.sigma_f * scale;
  summary.sigma_g = params.sigma_g * scale;
  const double reach = PNF_SUPPORT_IN_SIGMA_F * summary.sigma_f;
  // Counted before any list is allocated, so the memory is known first (SPEC, "Neighbour lists").
  check_pair_estimate(search, reach, options, summary);
  const std::vector<std::uint32_t> counts = search.count_within(reach);
  summary.neighbour_pairs = std::accumulate(counts.begin(), counts.end(), std::size_t(0));
  summary.neighbours_mean = double(summary.neighbour_pairs) / double(cloud.size());
  summary.neighbours_max = *std::max_element(counts.begin(), counts.end());
  summary.neighbour_seconds = seconds_since(start);

  if (params.iterations == 0) {
    result.normals.resize(cloud.size());
    for (std::size_t i = 0; i < cloud.size(); ++i) result.normals[i] = {unit[3 * i], unit[3 * i + 1], unit[3 * i + 2]};
    return result;
  }

  const pnf_coeffs c = pnf_make_coeffs(summary.sigma_f, summary.sigma_g);
  const Coefficients coefficients{c.inv_two_sigma_f2, c.inv_two_sigma_g2};
  std::size_t budget = options.memory_budget_bytes;
  for (;;) {
    const std::vector<Chunk> chunks = plan_chunks(counts, budget, backend.max_list_bytes());
    summary.chunks = chunks.size();
    summary.pass_seconds.clear();
    summary.kernel_seconds.clear();
    std::size_t largest = 0;  // bytes of the largest chunk's lists, to halve on a refusal
    try {
      start = Clock::now();
      backend.upload_cloud(search.positions(), ordered.normals);
      summary.upload_seconds += seconds_since(start);

      auto load_chunk = [&](const Chunk& chunk) {
        backend.wait();  // the previous chunk's kernel still reads the buffers; its time is the pass's
        auto t = Clock::now();
        std::size_t pairs = 0;
        for (std::size_t i = chunk.first; i < chunk.first + chunk.count; ++i) pairs += counts[i];
        largest = std::max(largest, csr_bytes(chunk.count, pairs));
        ListStorage storage = backend.begin_lists(chunk.first, chunk.count, pairs);
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

      std::vector<double> previous = ordered.normals;  // for the stop rule
      summary.mean_change_deg.clear();
      summary.passes_run = 0;
      for (int pass = 1; pass <= params.iterations; ++pass) {
        auto pass_start = Clock::now();
        for (const Chunk& chunk : chunks) {
          if (!whole) load_chunk(chunk);
          backend.run_chunk(coefficients);
        }
        summary.kernel_seconds.push_back(backend.end_pass());
        summary.pass_seconds.push_back(seconds_since(pass_start));
        summary.passes_run = pass;
        if (progress && !progress(PassProgress{pass, params.iterations, summary.pass_seconds.back()})) {
          throw Error(ErrorCode::cancelled, "cancelled after pass " + std::to_string(pass));
        }
        if (params.stop_change_deg > 0) {
          std::vector<double> current = backend.download_normals();
          summary.mean_change_deg.push_back(mean_angle_deg(previous, current));
          if (summary.mean_change_deg.back() < params.stop_change_deg) break;
          previous.swap(current);
        }
      }
      break;
    } catch (const DeviceMemoryError& e) {
      // A smaller chunk may fit where this one did not; one point's list is the floor.
      if (largest == 0 || largest <= csr_bytes(1, summary.neighbours_max)) {
        throw Error(ErrorCode::device, std::string(e.what()) + "; even one point's neighbour list does not fit");
      }
      budget = largest / 2;
      ++summary.allocation_retries;
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

}  // namespace pnf::detail
