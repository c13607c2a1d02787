// pnf::mpi::improve_normals_auto: `pnf filter --auto` across the ranks (pnf/mpi.hpp), as one
// process's improve_normals_auto (lib/src/auto/improve_normals_auto.cpp) does it.
#include <algorithm>
#include <string>
#include <vector>

#include "agreement.hpp"
#include "auto/judged_passes.hpp"
#include "judged_run.hpp"
#include "own_comm.hpp"
#include "pnf/error.hpp"
#include "pnf/improve_normals_auto.hpp"
#include "pnf/mpi.hpp"

namespace pnf::mpi {

DistributedAutoRun improve_normals_auto(MPI_Comm caller_comm, const CloudView& local, MutableVec3ArrayView normals_out,
                                        const FilterOptions& options, const ProgressCallback& progress,
                                        double stop_change_deg) {
  detail::OwnComm own_comm(caller_comm);
  const MPI_Comm comm = own_comm.get();
  const detail::Agreement agree(comm);
  DistributedAutoRun run;
  detail::RootJudge root;  // rank 0's judge over the whole cloud; its emptiness on every rank
  run.choice = detail::rule_choice(comm, agree, local, &root);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (stop_change_deg >= 0) run.choice.params.stop_change_deg = stop_change_deg;
  if (run.choice.params.iterations == 0 || root.empty) {
    run.summary = improve_normals(comm, local, normals_out, run.choice.params, options, progress);
    return run;
  }
  const std::vector<FilterParams> candidates = pnf::detail::judged_candidates(run.choice);
  std::vector<Vec3> best(local.size()), trial(local.size());
  double best_rms = -1;
  std::size_t best_candidate = 0;
  std::string judged;
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    FilterParams params = candidates[c];
    params.iterations = pnf::detail::judged_pass_budget(params, run.choice);
    detail::PassJudging judging;
    judging.root = rank == 0 ? &root : nullptr;
    judging.budget = params.iterations;
    const DistributedSummary summary =
        detail::improve_normals(comm, local, MutableVec3ArrayView(trial), params, options, progress, &judging);
    const double rms = judging.best_pass > 0 ? judging.rms_by_pass[std::size_t(judging.best_pass)]
                                             : pnf::detail::rms_to_beat(judging.rms_by_pass[0], judging.own_error_deg);
    if (c == 0) {
      judged = pnf::detail::judged_heading(judging.rms_by_pass[0], judging.own_error_deg, judging.samples,
                                           judging.fit_points);
    }
    judged += pnf::detail::judged_candidate(c, params, judging.rms_by_pass);
    if (c == 0 || rms < best_rms) {
      best_candidate = c;
      run.passes_kept = judging.best_pass;
      best_rms = rms;
      best.swap(trial);
      run.summary = summary;
    }
    run.judged_rms_deg.insert(run.judged_rms_deg.end(), judging.rms_by_pass.begin() + 1, judging.rms_by_pass.end());
  }
  for (std::size_t i = 0; i < local.size(); ++i) normals_out.set(i, best[i]);
  judged += pnf::detail::judged_outcome(best_candidate, run.passes_kept);
  if (run.passes_kept > 0) run.choice.params = candidates[best_candidate];
  run.choice.judged = judged;
  run.choice.params.iterations = run.passes_kept;
  return run;
}

}  // namespace pnf::mpi
