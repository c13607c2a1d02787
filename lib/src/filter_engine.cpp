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
// bounding-box centre in double before anything becomes float (SPEC, "Numerics"). In a
// distributed part the owned points come first, each group in curve order.
struct OrderedCloud {
  std::vector<std::uint32_t> order;  // order[k] = view index of point k
  std::vector<double> positions;     // N by 3
  std::vector<double> normals;       // N by 3, unit
};

OrderedCloud order_cloud(const CloudView& cloud, std::size_t owned) {
  OrderedCloud out;
  out.order = morton_order(cloud.positions);
  if (owned < cloud.size()) {
    std::stable_partition(out.order.begin(), out.order.end(), [&](std::uint32_t i) { return i < owned; });
  }
  const Vec3 centre = bounding_box(cloud.positions).centre();
  const std::size_t n = cloud.size();
  out.positions.resize(3 * n);
  out.normals.resize(3 * n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = out.order[k];
    const Vec3 normal = cloud.normals.at(i);
    // Normalised here, in double: the only copy of the normals the engine makes.
    const double length = std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    for (int c = 0; c < 3; ++c) {
      out.positions[3 * k + c] = cloud.positions.get(i, c) - centre[c];
      out.normals[3 * k + c] = normal[c] / length;
    }
  }
  return out;
}

double resolve_mean_radius(const CloudView& cloud, const FilterParams& params, const SpatialIndex& search,
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

// Sum of the angles in degrees between the first `count` rows of two N by 3 arrays of unit
// vectors (atan2: exact near 0).
double sum_angle_deg(const std::vector<double>& a, const std::vector<double>& b, std::size_t count) {
  double sum = 0;
  for (std::size_t i = 0; i < count; ++i) {
    sum += geometry::angle_radians({a[3 * i], a[3 * i + 1], a[3 * i + 2]}, {b[3 * i], b[3 * i + 1], b[3 * i + 2]});
  }
  return sum * 180.0 / geometry::kPi;
}

std::string gib(double bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f GiB", bytes / double(std::size_t(1) << 30));
  return text;
}

// Refuses, before the exact count, a neighbourhood so wide that the lists would pass
// options.memory.max_neighbour_pairs (every point neighbouring every other, say): that count
// alone would take hours. A sample of points gives the estimate, which is returned.
double check_pair_estimate(const SpatialIndex& search, double reach, const FilterOptions& options,
                           const FilterSummary& summary) {
  const double estimate = search.estimate_pairs(reach);
  if (estimate <= double(options.memory.max_neighbour_pairs)) return estimate;
  const double per_point = estimate / double(search.size());
  throw Error(ErrorCode::invalid_argument,
              "sigma_f = " + std::to_string(summary.sigma_f) + " model units gives about " +
                  std::to_string(std::llround(per_point)) + " neighbours per point, about " +
                  std::to_string(std::llround(estimate)) + " neighbour pairs (" + gib(estimate * 4) +
                  " of lists, as many kernel evaluations per pass), more than the limit of " +
                  std::to_string(options.memory.max_neighbour_pairs) +
                  " pairs; lower sigma_f, or raise MemoryPolicy::max_neighbour_pairs (pnf filter --max-pairs)");
}

// No device is slower than this (pair evaluations per second; the double reference on one core
// does about 2e7): work below max_seconds times this runs without a speed probe.
constexpr double kSlowestPairsPerSecond = 1e7;
// The probe times about this many pairs: milliseconds on a GPU, tens of them on a CPU.
constexpr double kProbePairs = 4e6;

// Times this device on a compact piece of the cloud (consecutive points along the curve, in
// its middle): building their lists, and one kernel pass over them. Returns the estimated
// seconds of the whole run, lists and passes, for `pairs` neighbour pairs per pass.
double estimate_run_seconds(FilterBackend& backend, const SpatialIndex& search, const OrderedCloud& ordered,
                            std::size_t owned, double reach, double pairs, int passes,
                            const Coefficients& coefficients) {
  const double per_point = std::max(1.0, pairs / double(std::max<std::size_t>(owned, 1)));
  const std::size_t m = std::clamp<std::size_t>(std::size_t(kProbePairs / per_point), 1, owned);
  const std::size_t first = (owned - m) / 2;
  auto start = Clock::now();
  std::vector<std::uint32_t> counts(first, 0);
  const std::vector<std::uint32_t> probed = search.count_within(reach, first, m);
  counts.insert(counts.end(), probed.begin(), probed.end());
  const std::size_t probe_pairs = std::accumulate(probed.begin(), probed.end(), std::size_t(0));
  backend.upload_cloud(search.positions(), ordered.normals);
  ListStorage storage = backend.begin_lists(first, m, probe_pairs);
  search.fill_lists(reach, first, m, counts, storage.offsets, storage.indices);
  backend.end_lists();
  const double list_seconds = seconds_since(start);
  start = Clock::now();
  backend.run_chunk(coefficients);
  double kernel_seconds = backend.end_pass();  // device time; the caller uploads the cloud again
  if (!(kernel_seconds > 0)) kernel_seconds = seconds_since(start);
  const double scale = pairs / double(std::max<std::size_t>(probe_pairs, 1));
  return scale * (list_seconds + double(passes) * kernel_seconds);
}

// The share of the list stage's progress given to the count (the rest is the fill): the two
// scan the same candidates; the fill also writes the lists. Dog setting: 0.77 s against 1.17 s
// (docs/performance.md).
constexpr double kCountShare = 0.4;

// The list build's progress, as SpatialIndex asks for it (a share f of its search), reported
// through the caller's callback as stage lists, fraction from + share * f.
WorkPoll list_poll(const ProgressCallback& progress, int passes_done, int passes, Clock::time_point stage_start,
                   double from, double share) {
  if (!progress) return {};
  return [&progress, passes_done, passes, stage_start, from, share](double f) {
    return progress(
        PassProgress{passes_done, passes, seconds_since(stage_start), ProgressStage::lists, from + share * f});
  };
}

// The end of a list build (fraction 1), so that every run reports its lists at least once.
void lists_done(const ProgressCallback& progress, int passes_done, int passes, Clock::time_point stage_start) {
  if (progress && !progress(PassProgress{passes_done, passes, seconds_since(stage_start), ProgressStage::lists, 1.0})) {
    throw Error(ErrorCode::cancelled, "cancelled after the neighbour lists were built");
  }
}

std::string seconds_text(double seconds) {
  char text[64];
  if (seconds < 120) {
    std::snprintf(text, sizeof text, "%.0f s", seconds);
  } else if (seconds < 7200) {
    std::snprintf(text, sizeof text, "%.0f min", seconds / 60);
  } else {
    std::snprintf(text, sizeof text, "%.1f h", seconds / 3600);
  }
  return text;
}

// A distributed part with no points at all still takes part in every pass's exchange and stop
// rule, so that the processes that have points are not left waiting.
void idle_passes(const DistributedPart& part, const FilterParams& params, const ProgressCallback& progress,
                 FilterSummary& summary) {
  const std::vector<double> none;
  std::vector<double> halo;
  for (int pass = 1; pass <= params.iterations; ++pass) {
    part.exchange_halo(none, halo);
    summary.passes_run = pass;
    summary.pass_seconds.push_back(0.0);
    if (progress && !progress(PassProgress{pass, params.iterations, 0.0})) {
      throw Error(ErrorCode::cancelled, "cancelled after pass " + std::to_string(pass));
    }
    if (params.stop_change_deg > 0) {
      double totals[2] = {0, 0};
      if (part.sum_over_processes) part.sum_over_processes(totals, 2);
      summary.mean_change_deg.push_back(totals[1] > 0 ? totals[0] / totals[1] : 0.0);
      if (summary.mean_change_deg.back() < params.stop_change_deg) break;
    }
    if (part.ends_passes && part.ends_passes()) break;
  }
}

}  // namespace

FilterSummary run_filter(FilterBackend& backend, const FilterOptions& options, const CloudView& cloud,
                         MutableVec3ArrayView normals_out, const FilterParams& params, const ProgressCallback& progress,
                         const DistributedPart* part) {
  params.validate();
  check_cloud(cloud, CloudRequirements::filter());
  const std::size_t owned = part ? part->owned : cloud.size();
  if (owned > cloud.size()) {
    throw Error(ErrorCode::invalid_argument,
                "a distributed part owns " + std::to_string(owned) + " of " + std::to_string(cloud.size()) + " points");
  }
  if (normals_out.count != owned) {
    throw Error(ErrorCode::invalid_argument, "the output normals hold " + std::to_string(normals_out.count) +
                                                 " rows for " + std::to_string(owned) + " points");
  }
  if (part && params.units == Units::radius && !(params.mean_radius > 0)) {
    throw Error(ErrorCode::invalid_argument, "a distributed part needs the mean radius given (params.mean_radius)");
  }

  FilterSummary summary;
  summary.points = owned;
  summary.backend = to_string(options.device.backend);
  summary.device = backend.description();
  if (cloud.size() == 0) {
    if (part) idle_passes(*part, params, progress, summary);
    return summary;
  }

  auto start = Clock::now();
  OrderedCloud ordered = order_cloud(cloud, owned);
  const SpatialIndex search(std::move(ordered.positions));  // no copy: the tree searches them in place
  summary.mean_radius = resolve_mean_radius(cloud, params, search, summary.radius_source);
  const double scale = params.units == Units::radius ? summary.mean_radius : 1.0;
  summary.sigma_f = params.sigma_f * scale;
  summary.sigma_g = params.sigma_g * scale;
  const double reach = PNF_SUPPORT_IN_SIGMA_F * summary.sigma_f;
  // Counted before any list is allocated, so the memory is known first (SPEC, "Neighbour lists").
  const double pair_estimate = check_pair_estimate(search, reach, options, summary);
  const pnf_coeffs c = pnf_make_coeffs(summary.sigma_f, summary.sigma_g);
  const Coefficients coefficients{c.inv_two_sigma_f2, c.inv_two_sigma_g2};
  // Work that would run past options.max_seconds is refused before the lists are built.
  const double owned_pairs = pair_estimate * double(owned) / double(cloud.size());
  const double work = owned_pairs * double(params.iterations + 1);  // the lists cost about one pass
  if (options.max_seconds > 0 && owned > 0 && work > options.max_seconds * kSlowestPairsPerSecond) {
    const double seconds =
        estimate_run_seconds(backend, search, ordered, owned, reach, owned_pairs, params.iterations, coefficients);
    if (seconds > options.max_seconds) {
      throw Error(ErrorCode::invalid_argument,
                  "this run would take about " + seconds_text(seconds) + " on " + summary.device + ": about " +
                      std::to_string(std::llround(owned_pairs)) + " neighbour pairs (" +
                      std::to_string(std::llround(owned_pairs / double(owned))) + " per point) times " +
                      std::to_string(params.iterations) + " passes, timed on a sample; the limit is " +
                      seconds_text(options.max_seconds) +
                      ". Lower sigma_f, or raise FilterOptions::max_seconds (pnf filter --max-seconds, 0: no limit)");
    }
  }
  const auto lists_start = Clock::now();
  // Halo points get no lists.
  // The count keeps the search blocks' candidates (about 3% of the lists' bytes on the dog) so
  // that the fills, the chunked runs' every pass included, do not search the tree again.
  BlockCandidates candidates;
  const std::vector<std::uint32_t> counts = search.count_within(
      reach, 0, owned, list_poll(progress, 0, params.iterations, lists_start, 0, kCountShare), &candidates);
  summary.neighbour_pairs = std::accumulate(counts.begin(), counts.end(), std::size_t(0));
  summary.neighbours_mean = owned > 0 ? double(summary.neighbour_pairs) / double(owned) : 0.0;
  summary.neighbours_max = owned > 0 ? *std::max_element(counts.begin(), counts.end()) : 0;
  summary.neighbour_seconds = seconds_since(start);

  // Writes the ordered normals' owned rows into the caller's buffer, re-normalised in double
  // (float32 unit vectors are unit only to about 1e-7).
  auto write_out = [&](const std::vector<double>& normals) {
    for (std::size_t k = 0; k < owned; ++k) {
      const double* n = &normals[3 * k];
      const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      normals_out.set(ordered.order[k], {n[0] / len, n[1] / len, n[2] / len});
    }
  };
  if (params.iterations == 0) {
    write_out(ordered.normals);
    return summary;
  }

  // The kept candidates count against the memory budget (they live as long as the lists).
  std::size_t budget = options.memory.budget_bytes;
  if (candidates.bytes() < budget / 4) {
    budget -= candidates.bytes();
  } else {
    candidates = BlockCandidates{};  // a budget too small for them: the fills search instead
  }
  std::vector<double> halo(3 * (cloud.size() - owned));
  for (;;) {
    const std::vector<Chunk> chunks =
        owned > 0 ? plan_chunks(counts, budget, backend.max_list_bytes()) : std::vector<Chunk>{};
    summary.chunks = chunks.size();
    summary.pass_seconds.clear();
    summary.kernel_seconds.clear();
    summary.degenerate_kept = 0;
    std::size_t largest = 0;  // bytes of the largest chunk's lists, to halve on a refusal
    try {
      start = Clock::now();
      backend.upload_cloud(search.positions(), ordered.normals);
      summary.upload_seconds += seconds_since(start);

      // Fills the chunk's lists; `from` and `share` place it in the list stage's progress.
      auto load_chunk = [&](const Chunk& chunk, int passes_done, Clock::time_point stage_start, double from,
                            double share) {
        backend.wait();  // the previous chunk's kernel still reads the buffers; its time is the pass's
        auto t = Clock::now();
        std::size_t pairs = 0;
        for (std::size_t i = chunk.first; i < chunk.first + chunk.count; ++i) pairs += counts[i];
        largest = std::max(largest, csr_bytes(chunk.count, pairs));
        ListStorage storage = backend.begin_lists(chunk.first, chunk.count, pairs);
        summary.upload_seconds += seconds_since(t);
        t = Clock::now();
        search.fill_lists(reach, chunk.first, chunk.count, counts, storage.offsets, storage.indices,
                          list_poll(progress, passes_done, params.iterations, stage_start, from, share), &candidates);
        summary.neighbour_seconds += seconds_since(t);
        t = Clock::now();
        backend.end_lists();
        summary.upload_seconds += seconds_since(t);
      };
      const bool whole = chunks.size() == 1;
      if (whole) {  // built once, kept on the device for every pass
        load_chunk(chunks[0], 0, lists_start, kCountShare, 1 - kCountShare);
        lists_done(progress, 0, params.iterations, lists_start);
        candidates = BlockCandidates{};  // built once: no refill will need them
      }

      std::vector<double> previous = ordered.normals;  // for the stop rule
      summary.mean_change_deg.clear();
      summary.passes_run = 0;
      // Chunked passes run their chunks forwards, then backwards, and so on: the chunk that ends a
      // pass is still in the buffer to start the next one, so each pass after the first refills one
      // chunk fewer. Every chunk of a pass reads the previous pass's normals, so the order does not
      // change the result.
      std::size_t loaded = whole ? 0 : chunks.size();  // the chunk whose lists the buffer holds
      for (int pass = 1; pass <= params.iterations; ++pass) {
        auto pass_start = Clock::now();
        for (std::size_t i = 0; i < chunks.size(); ++i) {
          const std::size_t c = pass % 2 == 1 ? i : chunks.size() - 1 - i;
          // Chunked: the lists stage of each pass is its chunks' fills, in turn.
          if (c != loaded) {
            load_chunk(chunks[c], pass - 1, pass_start, double(i) / double(chunks.size()), 1.0 / double(chunks.size()));
            loaded = c;
          }
          backend.run_chunk(coefficients);
        }
        summary.kernel_seconds.push_back(backend.end_pass());
        summary.degenerate_kept += backend.degenerate_kept();
        std::vector<double> current;
        if (part) {
          // The halo's rows of the new normals were not computed here: their owners send them.
          current = backend.download_normals();
          std::vector<double> mine(current.size() - halo.size());
          for (std::size_t k = 0; k < owned; ++k) {
            for (int c = 0; c < 3; ++c) mine[3 * ordered.order[k] + c] = current[3 * k + c];
          }
          part->exchange_halo(mine, halo);
          for (std::size_t k = owned; k < cloud.size(); ++k) {
            for (int c = 0; c < 3; ++c) current[3 * k + c] = halo[3 * (ordered.order[k] - owned) + c];
          }
          backend.replace_normals(current);
        }
        summary.pass_seconds.push_back(seconds_since(pass_start));
        summary.passes_run = pass;
        if (progress && !progress(PassProgress{pass, params.iterations, summary.pass_seconds.back()})) {
          throw Error(ErrorCode::cancelled, "cancelled after pass " + std::to_string(pass));
        }
        if (params.stop_change_deg > 0) {
          if (!part) current = backend.download_normals();
          double totals[2] = {sum_angle_deg(previous, current, owned), double(owned)};
          if (part && part->sum_over_processes) part->sum_over_processes(totals, 2);
          summary.mean_change_deg.push_back(totals[1] > 0 ? totals[0] / totals[1] : 0.0);
          if (summary.mean_change_deg.back() < params.stop_change_deg) break;
          previous.swap(current);
        }
        if (part && part->ends_passes && part->ends_passes()) break;
      }
      break;
    } catch (const DeviceMemoryError& e) {
      // The other processes of a distributed run have moved on: passes cannot start over.
      if (part && summary.passes_run > 0) {
        throw Error(ErrorCode::device, std::string(e.what()) + " after pass " + std::to_string(summary.passes_run) +
                                           " of a distributed run, which cannot start its passes over");
      }
      // A smaller chunk may fit where this one did not; one point's list is the floor.
      if (largest == 0 || largest <= csr_bytes(1, summary.neighbours_max)) {
        throw Error(ErrorCode::device, std::string(e.what()) + "; even one point's neighbour list does not fit");
      }
      budget = largest / 2;
      ++summary.allocation_retries;
    }
  }

  summary.device_bytes = backend.device_bytes();
  write_out(backend.download_normals());
  return summary;
}

}  // namespace pnf::detail
