// Internal to pnf::mpi: the distributed filter run with --auto's judged passes
// (improve_normals_auto across ranks; lib/src/auto/surface_judge.hpp for the judge).
#pragma once

#include <mpi.h>

#include <vector>

#include "auto/surface_judge.hpp"
#include "pnf/mpi.hpp"

namespace pnf::mpi::detail {

// What the judged run needs and what it tells: the same on every rank.
struct PassJudging {
  pnf::detail::JudgeGeometry geometry;  // of the pooled estimate; samples over the whole cloud
  int passes_past_best = 2;             // passes end when this many in a row did not beat the best
  std::vector<double> rms_by_pass;      // the judge's RMS (degrees) of the input, then each pass
  int best_pass = 0;                    // 0: the input
  double own_error_deg = 0;             // the judge's own error (SurfaceJudge::own_error_deg)
  int fit_points = 0;                   // the points of the fits that score (SurfaceJudge::scored)
};

// pnf::mpi::improve_normals; with `judging`, every pass is judged as one process's
// improve_normals_auto judges it, the passes end as it ends them, and normals_out gets the best
// pass's normals (the input's, normalised, when none beat them).
DistributedSummary improve_normals(MPI_Comm comm, const CloudView& local, MutableVec3ArrayView normals_out,
                                   const FilterParams& params, const FilterOptions& options,
                                   const ProgressCallback& progress, PassJudging* judging);

class Agreement;
// The pooled estimate (each rank's slice, pooled, with the one process's mean radius) and the
// rule on it: the first step of choose_filter_params and improve_normals_auto. Collective.
AutoChoice rule_choice(MPI_Comm comm, const Agreement& agree, const CloudView& local);

}  // namespace pnf::mpi::detail
