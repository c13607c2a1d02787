#include "filter_engine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <utility>

#include "chunk_plan.hpp"
#include "cloud_checks.hpp"
#include "geometry.hpp"
#include "mean_radius_internal.hpp"
#include "pnf/error.hpp"
#include "run_limits.hpp"
#include "spatial/spatial_order.hpp"

namespace pnf::detail {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The share of the list stage's progress given to the count (the rest is the fill): the two
// scan the same candidates; the fill also writes the lists. Dog setting: 0.77 s against 1.17 s
// (docs/performance.md).
constexpr double kCountShare = 0.4;

// With a progress callback, a pass runs in slices of about this many seconds, each waited for,
// so that progress is told and a cancel honoured within a pass (Ctrl-C in the CLI): a 1M-point
// pass takes 1.4 s on PoCL here, 5.5 s on the reference backend. The first slice has
// kFirstSlicePairs pairs; each next one as many as the last one's rate fills in kSliceSeconds,
// at least kMinSlicePairs so that the waits cost little on a fast device.
constexpr double kSliceSeconds = 0.2;
constexpr std::size_t kFirstSlicePairs = std::size_t(1) << 22;
constexpr std::size_t kMinSlicePairs = std::size_t(1) << 20;

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

// A part's lists come out in ascending index: its owned neighbours, then its halo ones, each run
// in curve order; one process's in ascending curve rank. Merged by curve rank, a point's list
// holds its neighbours in one process's order, so the kernel's sums round alike
// (DistributedPart::has_whole_frame). A merge of the two runs, not a sort: linear.
void sort_lists_along_curve(const ListStorage& lists, std::size_t count, std::size_t owned,
                            const std::vector<std::uint32_t>& rank) {
  const auto points = static_cast<std::int64_t>(count);
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::int64_t k = 0; k < points; ++k) {
    std::uint32_t* begin = lists.indices + lists.offsets[k];
    std::uint32_t* end = lists.indices + lists.offsets[k + 1];
    std::uint32_t* halo = std::lower_bound(begin, end, std::uint32_t(owned));
    std::inplace_merge(begin, halo, end, [&rank](std::uint32_t a, std::uint32_t b) { return rank[a] < rank[b]; });
  }
}

// After pass `pass`: tells progress (which may cancel), applies the stop rule on the change from
// `previous` to `current` (N by 3; downloaded here when empty) and asks the part whether the
// passes end. Returns true when they do; `previous` then holds `current`.
bool end_of_pass(FilterBackend* backend, const FilterParams& params, const ProgressCallback& progress,
                 const DistributedPart* part, std::size_t owned, int pass, std::vector<double>& previous,
                 std::vector<double>& current, FilterSummary& summary) {
  summary.passes_run = pass;
  if (progress && !progress(PassProgress{pass, params.iterations, summary.pass_seconds.back()})) {
    throw Error(ErrorCode::cancelled, "cancelled after pass " + std::to_string(pass));
  }
  if (params.stop_change_deg > 0) {
    if (!part) current = backend->download_normals();
    double totals[2] = {owned > 0 ? change_quanta(previous, current, owned) : 0.0, double(owned)};
    if (part && part->sum_over_processes) part->sum_over_processes(totals, 2);
    summary.mean_change_deg.push_back(totals[1] > 0 ? totals[0] / kChangeQuantaPerDegree / totals[1] : 0.0);
    if (summary.mean_change_deg.back() < params.stop_change_deg) return true;
    previous.swap(current);
  }
  return part && part->ends_passes && part->ends_passes();
}

// A distributed part with no points at all still takes part in every pass's exchange and stop
// rule, so that the processes that have points are not left waiting.
void idle_passes(const DistributedPart& part, const FilterParams& params, const ProgressCallback& progress,
                 FilterSummary& summary) {
  const std::vector<double> none;
  std::vector<double> halo, previous, current;
  for (int pass = 1; pass <= params.iterations; ++pass) {
    part.exchange_halo(none, halo);
    summary.pass_seconds.push_back(0.0);
    if (end_of_pass(nullptr, params, progress, &part, 0, pass, previous, current, summary)) break;
  }
}

// The lists step's result: each owned point's neighbour count and the search blocks' candidates
// kept for the fills (BlockCandidates).
struct ListCounts {
  std::vector<std::uint32_t> counts;
  BlockCandidates candidates;
  Clock::time_point start;  // of the list stage, for its progress
};

ListCounts count_lists(const PreparedCloud& prepared, const FilterParams& params, const ProgressCallback& progress,
                       FilterSummary& summary) {
  ListCounts lists;
  lists.start = Clock::now();
  // Halo points get no lists. The count keeps the search blocks' candidates (about 3% of the
  // lists' bytes on the dog) so that the fills, the chunked runs' every pass included, do not
  // search the tree again.
  lists.counts = prepared.search->count_within(prepared.plan.reach, 0, prepared.owned,
                                               list_poll(progress, 0, params.iterations, lists.start, 0, kCountShare),
                                               &lists.candidates);
  const std::vector<std::uint32_t>& counts = lists.counts;
  const std::size_t owned = prepared.owned;
  summary.neighbour_pairs = std::accumulate(counts.begin(), counts.end(), std::size_t(0));
  summary.neighbours_mean = owned > 0 ? double(summary.neighbour_pairs) / double(owned) : 0.0;
  summary.neighbours_max = owned > 0 ? *std::max_element(counts.begin(), counts.end()) : 0;
  return lists;
}

// The passes step: chunks planned within the memory budget, each pass over every chunk, the
// halo exchanged and the stop rule applied after each. When the device refuses a chunk's lists
// the passes start over with smaller chunks. Returns the final normals (N by 3, curve order).
class Passes {
 public:
  Passes(FilterBackend& backend, const FilterOptions& options, const PreparedCloud& prepared, ListCounts& lists,
         const FilterParams& params, const ProgressCallback& progress, const DistributedPart* part,
         FilterSummary& summary)
      : backend_(backend),
        options_(options),
        prepared_(prepared),
        lists_(lists),
        params_(params),
        progress_(progress),
        part_(part),
        summary_(summary) {}

  // The lists of one whole chunk are on the backend already, from a run over the same prepared
  // cloud and lists (run_filter's twin): the passes use them as they are.
  void reuse_whole_lists() { reuse_whole_lists_ = true; }
  // The prepared cloud's positions are on the backend already (another run over it put them
  // there): the passes upload only their normals.
  void reuse_positions() { cloud_on_backend_ = true; }
  // Whether the run left the lists of one whole chunk on the backend.
  bool whole_lists_loaded() const { return whole_lists_loaded_; }
  // Whether the passes have ended before params.iterations: the stop rule or the part said so.
  bool ended() const { return ended_; }
  // Whether run's plan keeps the lists as one whole chunk (unless the device then refuses it).
  bool plans_whole_lists() {
    return prepared_.owned > 0 && plan_chunks(lists_.counts, list_budget(), backend_.max_list_bytes()).size() == 1;
  }

  // Passes first_pass to last_pass (of params.iterations) from the prepared cloud's normals, which
  // are those after pass first_pass - 1: a pass reads only the normals of the pass before it, so a
  // run may stop after any pass and go on from its normals (run_filter's twin, pass by pass).
  std::vector<double> run(int first_pass, int last_pass) {
    first_pass_ = first_pass;
    last_pass_ = last_pass;
    std::size_t budget = list_budget();
    for (;;) {
      try {
        run_all(budget);
        break;
      } catch (const DeviceMemoryError& e) {
        // The other processes of a distributed run have moved on: passes cannot start over.
        if (part_ && summary_.passes_run > 0) {
          throw Error(ErrorCode::device, std::string(e.what()) + " after pass " + std::to_string(summary_.passes_run) +
                                             " of a distributed run, which cannot start its passes over");
        }
        // A smaller chunk may fit where this one did not; one point's list is the floor.
        if (largest_ == 0 || largest_ <= csr_bytes(1, summary_.neighbours_max)) {
          throw Error(ErrorCode::device, std::string(e.what()) + "; even one point's neighbour list does not fit");
        }
        budget = largest_ / 2;
        reuse_whole_lists_ = false;
        ++summary_.allocation_retries;
      }
    }
    return backend_.download_normals();
  }

 private:
  // The bytes the lists may take: the budget less the kept candidates, which live as long as the
  // lists; where they would take a quarter of it, they are dropped and the fills search instead.
  std::size_t list_budget() {
    const std::size_t budget = options_.memory.budget_bytes;
    if (lists_.candidates.bytes() < budget / 4) return budget - lists_.candidates.bytes();
    lists_.candidates = BlockCandidates{};
    return budget;
  }

  // Fills the chunk's lists; `from` and `share` place it in the list stage's progress.
  void load_chunk(const Chunk& chunk, int passes_done, Clock::time_point stage_start, double from, double share) {
    backend_.wait();  // the previous chunk's kernel still reads the buffers; its time is the pass's
    auto t = Clock::now();
    std::size_t pairs = 0;
    for (std::size_t i = chunk.first; i < chunk.first + chunk.count; ++i) pairs += lists_.counts[i];
    largest_ = std::max(largest_, csr_bytes(chunk.count, pairs));
    ListStorage storage = backend_.begin_lists(chunk.first, chunk.count, pairs);
    summary_.upload_seconds += seconds_since(t);
    t = Clock::now();
    prepared_.search->fill_lists(
        prepared_.plan.reach, chunk.first, chunk.count, lists_.counts, storage.offsets, storage.indices,
        list_poll(progress_, passes_done, params_.iterations, stage_start, from, share), &lists_.candidates);
    if (!prepared_.curve_rank.empty()) {
      sort_lists_along_curve(storage, chunk.count, prepared_.owned, prepared_.curve_rank);
    }
    summary_.neighbour_seconds += seconds_since(t);
    t = Clock::now();
    backend_.end_lists();
    summary_.upload_seconds += seconds_since(t);
  }

  // Runs pass `pass` over the chunk's points: in one go without a progress callback, else in
  // slices (kSliceSeconds), reported as stage filtering, fraction from + share * the chunk's share
  // done. A cancel returned mid-pass ends one process's run there; a distributed run's processes
  // end their passes together, so there it waits for the pass's end (end_of_pass).
  void run_slices(const Chunk& chunk, int pass, Clock::time_point pass_start, double from, double share) {
    const pnf_coeffs& coefficients = prepared_.plan.coefficients;
    if (!progress_) {
      backend_.run_chunk(coefficients, 0, chunk.count);
      return;
    }
    for (std::size_t begin = 0; begin < chunk.count;) {
      std::size_t end = begin, pairs = 0;
      while (end < chunk.count && (end == begin || pairs < slice_pairs_)) pairs += lists_.counts[chunk.first + end++];
      const auto start = Clock::now();
      backend_.run_chunk(coefficients, begin, end - begin);
      backend_.wait();
      const double seconds = seconds_since(start);
      if (seconds > 0) {
        const double next = double(pairs) * kSliceSeconds / seconds;
        slice_pairs_ = std::size_t(std::clamp(next, double(kMinSlicePairs), 4.0 * double(slice_pairs_)));
      }
      begin = end;
      const PassProgress report{pass - 1, params_.iterations, seconds_since(pass_start), ProgressStage::filtering,
                                from + share * double(begin) / double(chunk.count)};
      if (!progress_(report) && (!part_ || part_->one_process)) {
        throw Error(ErrorCode::cancelled, "cancelled during pass " + std::to_string(pass));
      }
    }
  }

  // The halo's rows of the new normals were not computed here: their owners send them.
  std::vector<double> exchange_halo() {
    const std::size_t owned = prepared_.owned, n = prepared_.order.size();
    std::vector<double> current = backend_.download_normals();
    std::vector<double> mine(3 * owned);
    for (std::size_t k = 0; k < owned; ++k) {
      for (int c = 0; c < 3; ++c) mine[3 * prepared_.order[k] + c] = current[3 * k + c];
    }
    part_->exchange_halo(mine, halo_);
    for (std::size_t k = owned; k < n; ++k) {
      for (int c = 0; c < 3; ++c) current[3 * k + c] = halo_[3 * (prepared_.order[k] - owned) + c];
    }
    backend_.replace_normals(current);
    return current;
  }

  void run_all(std::size_t budget) {
    const std::size_t owned = prepared_.owned;
    const std::vector<Chunk> chunks =
        owned > 0 ? plan_chunks(lists_.counts, budget, backend_.max_list_bytes()) : std::vector<Chunk>{};
    summary_.chunks = chunks.size();
    if (first_pass_ == 1) {
      summary_.pass_seconds.clear();
      summary_.kernel_seconds.clear();
      summary_.mean_change_deg.clear();
      summary_.degenerate_kept = 0;
      summary_.passes_run = 0;
    }
    largest_ = 0;
    halo_.assign(3 * (prepared_.order.size() - owned), 0.0);
    auto start = Clock::now();
    // The positions go up once; a later turn (run_beside_twin) or retry sends only its normals.
    if (cloud_on_backend_) {
      backend_.replace_normals(prepared_.normals);
    } else {
      backend_.upload_cloud(prepared_.search->positions(), prepared_.normals);
      cloud_on_backend_ = true;
    }
    summary_.upload_seconds += seconds_since(start);

    const bool whole = chunks.size() == 1;
    if (whole && reuse_whole_lists_) {
      largest_ = csr_bytes(owned, summary_.neighbour_pairs);
    } else if (whole) {  // built once, kept on the device for every pass
      load_chunk(chunks[0], 0, lists_.start, kCountShare, 1 - kCountShare);
      lists_done(progress_, 0, params_.iterations, lists_.start);
      lists_.candidates = BlockCandidates{};  // built once: no refill will need them
    }
    whole_lists_loaded_ = whole;

    std::vector<double> previous = prepared_.normals;  // for the stop rule
    // Chunked passes run their chunks forwards, then backwards, and so on: the chunk that ends a
    // pass is still in the buffer to start the next one, so each pass after the first refills one
    // chunk fewer. Every chunk of a pass reads the previous pass's normals, so the order does not
    // change the result.
    std::size_t loaded = whole ? 0 : chunks.size();  // the chunk whose lists the buffer holds
    for (int pass = first_pass_; pass <= last_pass_; ++pass) {
      auto pass_start = Clock::now();
      for (std::size_t i = 0; i < chunks.size(); ++i) {
        const std::size_t c = pass % 2 == 1 ? i : chunks.size() - 1 - i;
        // Chunked: the lists stage of each pass is its chunks' fills, in turn.
        if (c != loaded) {
          load_chunk(chunks[c], pass - 1, pass_start, double(i) / double(chunks.size()), 1.0 / double(chunks.size()));
          loaded = c;
        }
        run_slices(chunks[c], pass, pass_start, double(i) / double(chunks.size()), 1.0 / double(chunks.size()));
      }
      summary_.kernel_seconds.push_back(backend_.end_pass());
      summary_.degenerate_kept += backend_.degenerate_kept();
      std::vector<double> current;
      if (part_) current = exchange_halo();
      summary_.pass_seconds.push_back(seconds_since(pass_start));
      if (end_of_pass(&backend_, params_, progress_, part_, owned, pass, previous, current, summary_)) {
        ended_ = true;
        break;
      }
    }
  }

  FilterBackend& backend_;
  const FilterOptions& options_;
  const PreparedCloud& prepared_;
  ListCounts& lists_;
  const FilterParams& params_;
  const ProgressCallback& progress_;
  const DistributedPart* part_;
  FilterSummary& summary_;
  bool reuse_whole_lists_ = false;
  bool whole_lists_loaded_ = false;
  bool ended_ = false;
  bool cloud_on_backend_ = false;
  int first_pass_ = 1, last_pass_ = 0;
  std::size_t largest_ = 0;                     // bytes of the largest chunk's lists, to halve on a refusal
  std::size_t slice_pairs_ = kFirstSlicePairs;  // run_slices' next slice
  std::vector<double> halo_;
};

// The cloud's passes (`own`) and the twin's, over the same prepared cloud and lists; returns the
// cloud's normals. One process's two runs take turns pass by pass while the lists stay whole on
// the backend, so the twin runs no pass past the cloud's last (--auto's Stein estimate ends the
// cloud's passes two past its best, where the twin had run its whole budget: 3 of the rule's 8 on
// a clean tilted cloud, docs/auto.md "Time"). Otherwise the twin's passes all run first: chunked
// lists would be filled again at every turn, and a distributed run's processes must all take
// their halo exchanges in one order. The summary is the cloud's run; its list and upload times
// count both.
std::vector<double> run_beside_twin(Passes& own, FilterBackend& backend, const FilterOptions& options,
                                    PreparedCloud& prepared, ListCounts& lists, const FilterParams& params,
                                    const ProgressCallback& progress, const TwinRun& twin, bool one_process,
                                    FilterSummary& summary) {
  FilterSummary twin_summary = summary;
  twin_summary.neighbour_seconds = twin_summary.upload_seconds = 0;
  std::vector<double> mine = std::move(prepared.normals);
  prepared.normals = unit_rows(twin.normals, &prepared.order);
  Passes twin_passes(backend, options, prepared, lists, params, progress, twin.part, twin_summary);
  const int last = params.iterations;
  bool by_turns = one_process && twin_passes.plans_whole_lists();
  std::vector<double> theirs = twin_passes.run(1, by_turns ? 1 : last);
  if (by_turns && !twin_passes.whole_lists_loaded()) {  // the device refused the whole lists
    by_turns = false;
    if (!twin_passes.ended() && last > 1) {
      prepared.normals = std::move(theirs);
      twin_passes.run(2, last);
    }
  }
  own.reuse_positions();
  if (twin_passes.whole_lists_loaded()) {
    own.reuse_whole_lists();
    twin_passes.reuse_whole_lists();
  }
  for (int pass = 1;; ++pass) {
    prepared.normals = std::move(mine);
    mine = own.run(pass, by_turns ? pass : last);
    if (!by_turns || own.ended() || pass == last) break;
    if (!twin_passes.ended()) {
      prepared.normals = std::move(theirs);
      theirs = twin_passes.run(pass + 1, pass + 1);
    }
  }
  summary.neighbour_seconds += twin_summary.neighbour_seconds;
  summary.upload_seconds += twin_summary.upload_seconds;
  summary.allocation_retries += twin_summary.allocation_retries;
  return mine;
}

// Checks what run_filter is given before any work.
void check_run(const CloudView& cloud, MutableVec3ArrayView normals_out, const FilterParams& params,
               const DistributedPart* part, const TwinRun* twin) {
  params.validate();
  check_cloud(cloud, CloudRequirements::filter());
  if (twin) {
    CloudRequirements requirements = CloudRequirements::filter();
    requirements.caller = "the twin run";
    check_cloud(CloudView(cloud.positions, twin->normals, cloud.radii), requirements);
  }
  const std::size_t owned = part ? part->owned : cloud.size();
  if (owned > cloud.size()) {
    throw Error(ErrorCode::invalid_argument,
                "a distributed part owns " + std::to_string(owned) + " of " + std::to_string(cloud.size()) + " points");
  }
  if (normals_out.count != owned) {
    throw Error(ErrorCode::invalid_argument, "the output normals hold " + std::to_string(normals_out.count) +
                                                 " rows for " + std::to_string(owned) + " points");
  }
  if (part && !part->one_process && params.units == Units::radius && !(params.mean_radius > 0)) {
    throw Error(ErrorCode::invalid_argument, "a distributed part needs the mean radius given (params.mean_radius)");
  }
}

}  // namespace

std::vector<double> unit_rows(const Vec3ArrayView& normals, const std::vector<std::uint32_t>* order) {
  const std::size_t n = order ? order->size() : normals.count;
  std::vector<double> rows(3 * n);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3 normal = normals.at(order ? (*order)[k] : k);
    // Normalised here, in double: the engine's one copy of each set of normals.
    const double length = std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    for (int c = 0; c < 3; ++c) rows[3 * k + c] = normal[c] / length;
  }
  return rows;
}

PreparedCloud prepare_cloud(const CloudView& cloud, const FilterParams& params, std::size_t owned,
                            const DistributedPart* part) {
  PreparedCloud out;
  out.owned = owned;
  const bool whole_frame = part && part->has_whole_frame;
  // The curve with ties by the positions' and normals' bits: the same order, and so the same
  // lists, sums and normals, for any row order of the input.
  out.order = morton_order(cloud.positions, &cloud.normals, whole_frame ? &part->whole_curve : nullptr);
  if (owned < cloud.size()) {
    std::vector<std::uint32_t> rank_of_view(cloud.size());
    for (std::size_t k = 0; k < out.order.size(); ++k) rank_of_view[out.order[k]] = std::uint32_t(k);
    std::stable_partition(out.order.begin(), out.order.end(), [&](std::uint32_t i) { return i < owned; });
    out.curve_rank.resize(cloud.size());
    for (std::size_t k = 0; k < out.order.size(); ++k) out.curve_rank[k] = rank_of_view[out.order[k]];
  }
  // Positions reach the kernels as floats: re-centred on the middle of the points (not of their
  // box, which one far point can move away from all the others).
  const Vec3 centre = whole_frame ? part->whole_centre : sample_median(cloud.positions, out.order);
  out.normals = unit_rows(cloud.normals, &out.order);
  // No copy: searched in place.
  out.search = std::make_unique<SpatialIndex>(centred_rows(cloud.positions, centre, &out.order));
  MeanRadius radius;
  if (params.units == Units::radius) {
    radius = resolve_mean_radius(params.mean_radius, cloud.radii, cloud.size(),
                                 [&] { return estimate_mean_radius(*out.search); });
  }
  out.plan = make_filter_plan(params, radius);
  return out;
}

FilterSummary run_filter(FilterBackend& backend, const FilterOptions& options, const CloudView& cloud,
                         MutableVec3ArrayView normals_out, const FilterParams& params, const ProgressCallback& progress,
                         const DistributedPart* part, const TwinRun* twin) {
  check_run(cloud, normals_out, params, part, twin);
  const std::size_t owned = part ? part->owned : cloud.size();
  FilterSummary summary;
  summary.points = owned;
  summary.backend = to_string(options.device.backend);
  summary.device = backend.description();
  if (cloud.size() == 0) {
    if (part) {
      check_idle_pair_limit(*part, options);
      if (twin && twin->part) idle_passes(*twin->part, params, progress, summary);
      idle_passes(*part, params, progress, summary);
    }
    return summary;
  }

  // Step 1, prepare; then the refusals, before any list is allocated, so that the memory and the
  // time are known first (docs/method.md, "Neighbour lists").
  const auto start = Clock::now();
  PreparedCloud prepared = prepare_cloud(cloud, params, owned, part);
  summary.mean_radius = prepared.plan.radius.value;
  summary.radius_source = prepared.plan.radius.source;
  summary.sigma_f = prepared.plan.sigma_f;
  summary.sigma_g = prepared.plan.sigma_g;
  const double pair_estimate = check_pair_limit(prepared, options, part);
  // A twin runs as many passes again.
  check_time_limit(backend, prepared, options, pair_estimate, params.iterations * (twin ? 2 : 1), summary.device);

  // Step 2, the lists' counts.
  ListCounts lists = count_lists(prepared, params, progress, summary);
  summary.neighbour_seconds = seconds_since(start);

  // Step 3, the passes; the owned rows written into the caller's buffer, re-normalised in
  // double (float32 unit vectors are unit only to about 1e-7).
  std::vector<double> normals;
  if (params.iterations == 0) {
    normals = prepared.normals;
  } else {
    Passes passes(backend, options, prepared, lists, params, progress, part, summary);
    if (twin) {
      const bool one_process = !part || part->one_process;
      normals =
          run_beside_twin(passes, backend, options, prepared, lists, params, progress, *twin, one_process, summary);
    } else {
      normals = passes.run(1, params.iterations);
    }
    summary.device_bytes = backend.device_bytes();
  }
  for (std::size_t k = 0; k < owned; ++k) {
    const double* n = &normals[3 * k];
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    normals_out.set(prepared.order[k], {n[0] / len, n[1] / len, n[2] / len});
  }
  return summary;
}

double change_quanta(const std::vector<double>& a, const std::vector<double>& b, std::size_t count) {
  std::int64_t quanta = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const double radians =
        geometry::angle_radians({a[3 * i], a[3 * i + 1], a[3 * i + 2]}, {b[3 * i], b[3 * i + 1], b[3 * i + 2]});
    quanta += std::llround(radians * (180.0 / geometry::kPi) * kChangeQuantaPerDegree);
  }
  return double(quanta);
}

}  // namespace pnf::detail
