// Internal to pnf::mpi: the distributed filter run with --auto's judged passes
// (improve_normals_auto across ranks; lib/src/auto/surface_judge.hpp for the judge).
#pragma once

#include <mpi.h>

#include <cstddef>
#include <limits>
#include <vector>

#include "auto/held_out_planes.hpp"
#include "auto/judged_passes.hpp"
#include "auto/stein_risk.hpp"
#include "auto/surface_judge.hpp"
#include "pnf/mpi.hpp"

namespace pnf::mpi::detail {

// Rank 0's judge over the whole cloud, gathered there for the choice (rule_choice), with the
// whole cloud's input normals, normalised: what one process's improve_normals_auto judges with.
// `empty` is known on every rank.
struct RootJudge {
  pnf::detail::SurfaceJudge judge;
  std::vector<double> input_normals;    // N by 3, the concatenation of the ranks' rows
  pnf::detail::SteinRisk stein;         // where Stein's estimate decides (pnf::detail::stein_decides)
  pnf::detail::HeldOutPlanes held_out;  // where the held-out check may run (pnf::detail::tries_held_out)
  bool empty = true;
  int plane_fits = 0;            // SurfaceJudge::plane_fits, known on every rank
  int fit_points = 0;            // SurfaceJudge::scored, known on every rank
  std::size_t cloud_points = 0;  // the whole cloud's, known on every rank
  std::size_t samples = 0;       // the judge's (SurfaceJudge::size), known on every rank
  // The judge's RMS of the input and its own error, known on every rank where the input's own noise
  // bounds the judge's error (pnf::detail::noise_bounding_judge_deg: judge_cannot_see_gains needs
  // them before any pass); 0 elsewhere.
  double input_rms_deg = 0, own_error_deg = 0;
};

// What the judged run needs and what it tells: the same on every rank.
struct PassJudging {
  const RootJudge* root = nullptr;  // rank 0's, where the passes are scored; null elsewhere
  int budget = 0;                   // the passes the judge scores (pnf::detail::judged_pass_budget; 0: none)
  std::vector<double> rms_by_pass;  // the judge's RMS (degrees) of the input, then each pass
  int best_pass = 0;                // 0: the input
  double own_error_deg = 0;         // the judge's own error (SurfaceJudge::own_error_deg)
  double input_noise_deg = -1;      // set by the caller: pnf::detail::noise_bounding_judge_deg
  double error_deg = 0;             // the error weighed: pnf::detail::judge_error_deg
  int fit_points = 0;               // the points of the fits that score (SurfaceJudge::scored)
  int under_support = 0;            // SurfaceJudge::under_support
  int plane_fits = 0;               // SurfaceJudge::plane_fits
  std::size_t samples = 0;          // the judge's samples
  pnf::detail::Fallback fallback;   // where it runs one (candidate above 0): judged against its bar
  // The lowest judged RMS of the settings judged before (one process's running best): a pass is
  // kept, and the passes end (judged_passes_end), against the lower of it and the bar.
  double best_before = std::numeric_limits<double>::infinity();
  // The held-out check (pnf::detail::tries_held_out), as one process's judged_run runs it: with
  // `check`, rank 0 also scores every pass against its held-out planes until a pass of the
  // judge's is kept or the check's passes end; a pass under the lower of `checked_best_before` and
  // the input's disagreement whose gain passes kHeldOutMinGainZ is kept (`checked_best_pass`, 0:
  // none) and its normals go to `checked_out` (this rank's rows). `checked_by_pass`: the input's
  // disagreement, then each pass's; `checked_samples`: the planes' samples.
  bool check = false;
  double checked_best_before = std::numeric_limits<double>::infinity();
  std::vector<double> checked_by_pass;
  int checked_best_pass = 0;
  std::size_t checked_samples = 0;
  MutableVec3ArrayView checked_out;
  // The run from the probed input where Stein's estimate decides (every rank): its passes are
  // only recorded, all of `budget` (or as many as the stop rule lets run: `passes`).
  bool probing = false;
  std::vector<std::vector<double>> samples_by_pass;  // rank 0: SteinRisk::at_samples of each pass
  int passes = 0;
  // The run that Stein's estimate decides (every rank), as one process's stein_run: rms_by_pass
  // then holds the estimates (the input's noise first, set by the caller) and a pass is kept
  // below `to_beat` (the lowest estimate of the settings before). `probed`: the probing run's
  // (its samples on rank 0).
  bool stein = false;
  const PassJudging* probed = nullptr;
  double to_beat = 0;
};

// The probed twin of a judged run, as one process's NormalFilter::run_observed_after_twin runs
// it: the same points with other normals (`normals`: this rank's rows), whose passes run first
// over the same partition, halo and neighbour lists, each told to `judging` (a probing one).
struct TwinJudging {
  Vec3ArrayView normals;
  PassJudging* judging = nullptr;
};

// pnf::mpi::improve_normals; with `judging`, every pass is judged as one process's
// improve_normals_auto judges it, the passes end as it ends them, and normals_out gets the best
// pass's normals (the input's, normalised, when none beat them); with `twin`, the twin's passes
// first.
DistributedSummary improve_normals(MPI_Comm comm, const CloudView& local, MutableVec3ArrayView normals_out,
                                   const FilterParams& params, const FilterOptions& options,
                                   const ProgressCallback& progress, PassJudging* judging,
                                   const TwinJudging* twin = nullptr);

// Every rank's rows on rank 0, in rank order: the cloud one process would read (the
// concatenation of the ranks' inputs), so that rank 0 computes what one process computes; empty
// on the other ranks. Refuses (on every rank) more than 2^31 values, an MPI count. Collective.
std::vector<double> gather_rows(MPI_Comm comm, const std::vector<double>& mine);

class Agreement;
// One process's estimate and rule: every rank's points gathered on rank 0 in rank order (the
// cloud one process would read), estimated there and the choice sent to every rank; with
// `root`, rank 0 also keeps the judge (and every rank learns whether it is empty). The first
// step of choose_filter_params and improve_normals_auto. Collective.
AutoChoice rule_choice(MPI_Comm comm, const Agreement& agree, const CloudView& local, RootJudge* root);

}  // namespace pnf::mpi::detail
