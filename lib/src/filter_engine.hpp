// The filter's driver, independent of the backend, in three steps: prepare (validation, curve
// ordering and re-centring, the spatial index, the mean radius and the run's plan), lists (the
// neighbour count, chunk planning) and passes (chunked passes, progress, the stop rule, a
// distributed part's halo exchange), then mapping back to input order.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "filter_backend.hpp"
#include "filter_plan.hpp"
#include "pnf/normal_filter.hpp"
#include "spatial/spatial_index.hpp"
#include "spatial/spatial_order.hpp"

namespace pnf::detail {

// One process's share of a distributed run (pnf/mpi.hpp): the view's first `owned` points are
// this process's; the rest are its halo, other processes' points within reach of its own. Lists
// are built and normals computed for the owned points only; the halo's normals come from their
// owners after every pass.
struct DistributedPart {
  std::size_t owned = 0;
  // Called after every pass with the owned points' new normals (owned by 3, view order); fills
  // `halo` ((N - owned) by 3, view order) with the halo's new normals from their owners.
  std::function<void(const std::vector<double>& owned_normals, std::vector<double>& halo)> exchange_halo;
  // Sums values over every process (the stop rule's change and its point count), so every
  // process takes the same decision. Identity when empty.
  std::function<void(double* values, int count)> sum_over_processes;
  // Asked after every pass's exchange (and stop rule): true ends the passes there, as the stop
  // rule does. In a distributed run every process must answer alike (from summed figures).
  std::function<bool()> ends_passes;
  // Adds `count` values over every process, after making sure none has failed (a distributed
  // run's agreement): the job's pair estimate, which every process refuses alike
  // (check_pair_limit). Empty: no job-wide limit.
  std::function<void(double* values, int count)> job_sum;
  // No other process takes part (run_observed's observer): a cancel may end a pass midway, where
  // the processes of a distributed run end their passes together.
  bool one_process = false;
  // The whole cloud's curve frame and origin (a distributed run's: sample_median's, as one process's),
  // where set: the part orders and re-centres its points as one process does the whole cloud,
  // and each list holds its neighbours in the whole cloud's curve order, so every point's sums
  // round as in one process and the normals are the same bits (docs/method.md).
  bool has_whole_frame = false;
  MortonFrame whole_curve;
  Vec3 whole_centre = {0, 0, 0};
};

// The cloud as the backends see it, with its index and plan: the first step of a run.
struct PreparedCloud {
  // order[k] = the view index of point k: along the Morton curve, a distributed part's owned
  // points first (each group in curve order).
  std::vector<std::uint32_t> order;
  std::vector<double> normals;           // N by 3, unit (normalised in double), in that order
  std::unique_ptr<SpatialIndex> search;  // over the positions in that order, re-centred on the
                                         // points' middle in double (sample_median, docs/method.md)
  std::size_t owned = 0;                 // the points filtered: [0, owned) in that order
  FilterPlan plan;
  // A part's points' ranks along the curve before the owned points were put first (empty when
  // nothing moved): the order its lists are sorted in (sort_lists_along_curve).
  std::vector<std::uint32_t> curve_rank;
};

// The rows of `normals`, in `order` where given (order[k]: the row of the k-th), each divided by
// its length in double: the one normalisation of the engine's copies, of the input the judge and
// Stein's estimate read, and of the rows a run that keeps its input returns. Zero rows must be
// refused before (check_cloud).
std::vector<double> unit_rows(const Vec3ArrayView& normals, const std::vector<std::uint32_t>* order = nullptr);

// Orders and re-centres a non-empty, checked cloud, indexes it and makes the plan for `params`
// (validated), resolving the mean radius as FilterParams says (given, the radii's mean, or the
// estimate on this index).
// With `part`'s whole frame, the part's curve and centre are the whole cloud's.
PreparedCloud prepare_cloud(const CloudView& cloud, const FilterParams& params, std::size_t owned,
                            const DistributedPart* part = nullptr);

// The stop rule's change: the sum over the first `count` rows of two N by 3 arrays of unit
// vectors of the angle between them, each rounded to whole quanta of 2^-16 degrees
// (kChangeQuantaPerDegree). Integers add exactly in any order, so a distributed run's parts,
// summed as doubles (exact below 2^53: 1.4e11 degrees, a 34-degree mean change on 4e9 points),
// give one process's total bit for bit and stop after the same pass.
constexpr double kChangeQuantaPerDegree = 65536.0;
double change_quanta(const std::vector<double>& a, const std::vector<double>& b, std::size_t count);

// A run of the same passes from other normals on the same positions, before the cloud's own
// (NormalFilter::run_observed_after_twin): it shares the cloud's order, index and neighbour
// lists, built once. Its normals are told to its part's observer (a whole part: one process) and
// then dropped.
struct TwinRun {
  Vec3ArrayView normals;  // N rows, checked as the cloud's normals are
  const DistributedPart* part = nullptr;
};

// NormalFilter::run on `backend` (see normal_filter.hpp for the contract). When the backend
// reports that the device refused an allocation (DeviceMemoryError), the run starts over with
// chunks half the size of the one refused, down to a single point's list. With `part`, only the
// owned points are filtered and written (normals_out has `owned` rows), and the mean radius must
// be given (params.mean_radius, or absolute units): one process cannot estimate it for all.
// With `twin`, its passes run first (none when params.iterations is 0).
FilterSummary run_filter(FilterBackend& backend, const FilterOptions& options, const CloudView& cloud,
                         MutableVec3ArrayView normals_out, const FilterParams& params, const ProgressCallback& progress,
                         const DistributedPart* part = nullptr, const TwinRun* twin = nullptr);

}  // namespace pnf::detail
