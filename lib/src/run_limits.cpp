#include "run_limits.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "pnf/error.hpp"

namespace pnf::detail {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::string gib(double bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f GiB", bytes / double(std::size_t(1) << 30));
  return text;
}

std::string seconds_text(double seconds) {
  char text[64];
  if (seconds < 10) {
    std::snprintf(text, sizeof text, "%.2g s", seconds);  // a limit of 0.001 s read "0 s"
  } else if (seconds < 120) {
    std::snprintf(text, sizeof text, "%.0f s", seconds);
  } else if (seconds < 7200) {
    std::snprintf(text, sizeof text, "%.0f min", seconds / 60);
  } else {
    std::snprintf(text, sizeof text, "%.1f h", seconds / 3600);
  }
  return text;
}

// No device is slower than this (pair evaluations per second; the double reference on one core
// does about 2e7): work below max_seconds times this runs without a speed probe.
constexpr double kSlowestPairsPerSecond = 1e7;
// The probe times about this many pairs: milliseconds on a GPU, tens of them on a CPU.
constexpr double kProbePairs = 4e6;

// Times this device on a compact piece of the cloud (consecutive points along the curve, in
// its middle): building their lists, and one kernel pass over them. Returns the estimated
// seconds of the whole run, lists and passes, for `pairs` neighbour pairs per pass.
double estimate_run_seconds(FilterBackend& backend, const PreparedCloud& prepared, double pairs, int passes) {
  const SpatialIndex& search = *prepared.search;
  const double reach = prepared.plan.reach;
  const std::size_t owned = prepared.owned;
  const double per_point = std::max(1.0, pairs / double(std::max<std::size_t>(owned, 1)));
  const std::size_t m = std::clamp<std::size_t>(std::size_t(kProbePairs / per_point), 1, owned);
  const std::size_t first = (owned - m) / 2;
  auto start = Clock::now();
  std::vector<std::uint32_t> counts(first, 0);
  const std::vector<std::uint32_t> probed = search.count_within(reach, first, m);
  counts.insert(counts.end(), probed.begin(), probed.end());
  const std::size_t probe_pairs = std::accumulate(probed.begin(), probed.end(), std::size_t(0));
  backend.upload_cloud(search.positions(), prepared.normals);
  ListStorage storage = backend.begin_lists(first, m, probe_pairs);
  search.fill_lists(reach, first, m, counts, storage.offsets, storage.indices);
  backend.end_lists();
  const double list_seconds = seconds_since(start);
  start = Clock::now();
  backend.run_chunk(prepared.plan.coefficients, 0, m);
  double kernel_seconds = backend.end_pass();  // device time
  if (!(kernel_seconds > 0)) kernel_seconds = seconds_since(start);
  const double scale = pairs / double(std::max<std::size_t>(probe_pairs, 1));
  return scale * (list_seconds + double(passes) * kernel_seconds);
}

}  // namespace

namespace {

// Refuses `pairs` over `points` when past the limit; `what` names the run ("" or " for the whole job").
void refuse_past_limit(double pairs, double points, double sigma_f, const FilterOptions& options,
                       const std::string& what) {
  if (pairs <= double(options.memory.max_neighbour_pairs)) return;
  const double per_point = points > 0 ? pairs / points : 0;
  throw Error(ErrorCode::invalid_argument,
              "sigma_f = " + std::to_string(sigma_f) + " model units gives about " +
                  std::to_string(std::llround(per_point)) + " neighbours per point, about " +
                  std::to_string(std::llround(pairs)) + " neighbour pairs" + what + " (" + gib(pairs * 4) +
                  " of lists, as many kernel evaluations per pass), more than the limit of " +
                  std::to_string(options.memory.max_neighbour_pairs) +
                  " pairs; lower sigma_f, or raise MemoryPolicy::max_neighbour_pairs (pnf filter --max-pairs)");
}

}  // namespace

double check_pair_limit(const PreparedCloud& prepared, const FilterOptions& options, const DistributedPart* part) {
  const SpatialIndex& search = *prepared.search;
  const double estimate = search.estimate_pairs(prepared.plan.reach);
  if (part && part->job_sum) {
    // The owned points' share (the halo gets no lists), added over the processes.
    double job[4] = {estimate * double(prepared.owned) / double(search.size()), double(prepared.owned),
                     prepared.plan.sigma_f, 1.0};
    part->job_sum(job, 4);
    refuse_past_limit(job[0], job[1], job[2] / job[3], options, " for the whole job");
    return estimate;
  }
  refuse_past_limit(estimate, double(search.size()), prepared.plan.sigma_f, options, "");
  return estimate;
}

void check_idle_pair_limit(const DistributedPart& part, const FilterOptions& options) {
  if (!part.job_sum) return;
  // The processes with points add their sigma_f (the same plan on each) and a 1 each.
  double job[4] = {0, 0, 0, 0};
  part.job_sum(job, 4);
  refuse_past_limit(job[0], job[1], job[3] > 0 ? job[2] / job[3] : 0, options, " for the whole job");
}

void check_time_limit(FilterBackend& backend, const PreparedCloud& prepared, const FilterOptions& options,
                      double pair_estimate, int passes, const std::string& device) {
  const std::size_t owned = prepared.owned;
  const double owned_pairs = pair_estimate * double(owned) / double(prepared.search->size());
  const double work = owned_pairs * double(passes + 1);  // the lists cost about one pass
  if (!(options.max_seconds > 0 && owned > 0 && work > options.max_seconds * kSlowestPairsPerSecond)) return;
  const double seconds = estimate_run_seconds(backend, prepared, owned_pairs, passes);
  if (!(seconds > options.max_seconds)) return;
  throw Error(ErrorCode::invalid_argument,
              "this run would take about " + seconds_text(seconds) + " on " + device + ": about " +
                  std::to_string(std::llround(owned_pairs)) + " neighbour pairs (" +
                  std::to_string(std::llround(owned_pairs / double(owned))) + " per point) times " +
                  std::to_string(passes) + " passes, timed on a sample; the limit is " +
                  seconds_text(options.max_seconds) +
                  ". Lower sigma_f, or raise FilterOptions::max_seconds (pnf filter --max-seconds, 0: no limit)");
}

}  // namespace pnf::detail
