// pnf::mpi::improve_normals_auto: `pnf filter --auto` across the ranks (pnf/mpi.hpp), as one
// process's improve_normals_auto (lib/src/auto/improve_normals_auto.cpp) does it.
#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#include "agreement.hpp"
#include "auto/judged_passes.hpp"
#include "filter_engine.hpp"
#include "judged_run.hpp"
#include "own_comm.hpp"
#include "pnf/error.hpp"
#include "pnf/improve_normals_auto.hpp"
#include "pnf/mpi.hpp"

namespace pnf::mpi {
namespace {

// This rank's input normals, made unit, with the rows among Stein's samples nudged by the probe
// (rank 0 sends the samples' rows of the whole cloud, the ranks' rows in rank order, and their
// nudges): the rows one process's probed run filters. Collective.
std::vector<double> probed_rows(MPI_Comm comm, const detail::RootJudge& root, const CloudView& local) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  std::vector<double> nudges;  // row, then the probe's x y z, per sample
  if (rank == 0) {
    const std::vector<std::size_t>& samples = root.stein.samples();
    for (std::size_t s = 0; s < samples.size(); ++s) {
      nudges.push_back(double(samples[s]));
      for (int c = 0; c < 3; ++c) nudges.push_back(root.stein.probes()[3 * s + std::size_t(c)]);
    }
  }
  unsigned long long size = nudges.size();
  detail::check_mpi(MPI_Bcast(&size, 1, MPI_UNSIGNED_LONG_LONG, 0, comm), "MPI_Bcast");
  nudges.resize(size);
  detail::check_mpi(MPI_Bcast(nudges.data(), int(size), MPI_DOUBLE, 0, comm), "MPI_Bcast");
  unsigned long long mine = local.size(), first = 0;
  detail::check_mpi(MPI_Exscan(&mine, &first, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm), "MPI_Exscan");
  if (rank == 0) first = 0;  // MPI_Exscan leaves rank 0's undefined
  std::vector<double> rows = pnf::detail::unit_rows(local.normals);
  for (std::size_t k = 0; k < nudges.size(); k += 4) {
    const auto row = static_cast<unsigned long long>(nudges[k]);
    if (row < first || row >= first + mine) continue;
    for (int c = 0; c < 3; ++c) {
      rows[3 * (row - first) + std::size_t(c)] += pnf::detail::kSteinProbeStep * nudges[k + 1 + std::size_t(c)];
    }
  }
  return rows;
}

// One process's stein_run (lib/src/auto/improve_normals_auto.cpp) across the ranks: for each
// setting, its passes from the probed input (the twin), then from the input with each pass estimated on
// rank 0 as it ends; the lowest estimate of all settings kept unless the judge scores it above
// the input.
void stein_run(MPI_Comm comm, const CloudView& local, MutableVec3ArrayView normals_out, const FilterOptions& options,
               const ProgressCallback& progress, detail::RootJudge& root, DistributedAutoRun& run) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const std::vector<FilterParams> candidates = pnf::detail::stein_candidates(run.choice);
  const double noise = pnf::detail::stein_noise_deg(run.choice);  // rank 0's SteinRisk has it too
  const std::vector<double> probed_input = probed_rows(comm, root, local);
  const std::vector<double> unit = pnf::detail::unit_rows(local.normals);
  std::vector<Vec3> input(local.size()), trial(local.size());
  for (std::size_t i = 0; i < local.size(); ++i) input[i] = {unit[3 * i], unit[3 * i + 1], unit[3 * i + 2]};
  std::vector<Vec3> best = input;
  double best_risk = noise;
  std::size_t best_candidate = 0;
  std::string estimated = pnf::detail::stein_heading(run.choice);
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    FilterParams params = candidates[c];
    params.iterations = pnf::detail::judged_pass_budget(params, run.choice, root.fit_points);
    detail::PassJudging probing;
    probing.root = rank == 0 ? &root : nullptr;
    probing.probing = true;
    probing.budget = params.iterations;
    const detail::TwinJudging twin{Vec3ArrayView(probed_input.data(), local.size()), &probing};
    detail::PassJudging judging;
    judging.root = probing.root;
    judging.stein = true;
    judging.probed = &probing;
    judging.budget = params.iterations;
    judging.to_beat = best_risk;
    judging.rms_by_pass = {noise};
    const DistributedSummary summary =
        detail::improve_normals(comm, local, MutableVec3ArrayView(trial), params, options, progress, &judging, &twin);
    estimated += pnf::detail::judged_candidate(c, params, judging.rms_by_pass);
    if (judging.best_pass > 0) {
      best.swap(trial);
      best_candidate = c;
      run.passes_kept = judging.best_pass;
      best_risk = judging.rms_by_pass[std::size_t(judging.best_pass)];
    }
    if (c == best_candidate) run.summary = summary;
    run.judged_rms_deg.insert(run.judged_rms_deg.end(), judging.rms_by_pass.begin() + 1, judging.rms_by_pass.end());
  }
  // The judge scores the input and the pass kept (gathered on rank 0 as one process holds it).
  double judged[2] = {0, 0};
  std::vector<double> kept;  // every rank takes the same branch: passes_kept is the same on all
  if (run.passes_kept > 0) {
    for (const Vec3& v : best) kept.insert(kept.end(), v.begin(), v.end());
    kept = detail::gather_rows(comm, kept);
  }
  if (rank == 0) {
    judged[0] = root.judge.input_rms_deg(root.input_normals.data());
    if (run.passes_kept > 0) judged[1] = root.judge.rms_deg(kept.data());
  }
  detail::check_mpi(MPI_Bcast(judged, 2, MPI_DOUBLE, 0, comm), "MPI_Bcast");
  const double input_judged = judged[0], best_judged = judged[1];
  if (best_judged > input_judged) {
    run.passes_kept = 0;
    best = input;
  }
  for (std::size_t i = 0; i < local.size(); ++i) normals_out.set(i, best[i]);
  if (run.passes_kept > 0) run.choice.params = candidates[best_candidate];
  run.choice.judged = pnf::detail::stein_judged(input_judged, best_judged) + estimated +
                      pnf::detail::judged_outcome(best_candidate, run.passes_kept);
  run.choice.params.iterations = run.passes_kept;
}

}  // namespace

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
  if (pnf::detail::stein_decides(run.choice)) {
    stein_run(comm, local, normals_out, options, progress, root, run);
    return run;
  }
  const double input_noise = pnf::detail::noise_bounding_judge_deg(run.choice, root.plane_fits);
  const double error = pnf::detail::judge_error_deg(root.input_rms_deg, root.own_error_deg, input_noise);
  if (pnf::detail::judge_cannot_see_gains(run.choice, root.plane_fits, error)) {
    // No pass, as one process: the input made unit, with the summary of the rule's setting.
    run.choice.params.iterations = 0;
    run.summary = improve_normals(comm, local, normals_out, run.choice.params, options, progress);
    run.choice.judged = pnf::detail::unseen_gains_judged(run.choice, root.input_rms_deg, root.own_error_deg, error);
    return run;
  }
  const std::vector<FilterParams> candidates = pnf::detail::judged_candidates(run.choice);
  std::vector<Vec3> best(local.size()), trial(local.size());
  double best_rms = -1;
  std::size_t best_candidate = 0;
  std::string judged;
  // The held-out check, as one process's improve_normals_auto runs it: its settings, the best
  // pass it has kept (this rank's rows) and its text.
  const bool held_out = pnf::detail::tries_held_out(run.choice, root.plane_fits);
  const bool too_wide = pnf::detail::judge_fits_too_wide(root.fit_points, root.cloud_points);
  if (too_wide && !held_out) {  // no pass to judge by, as one process
    run.choice.params.iterations = 0;
    run.summary = improve_normals(comm, local, normals_out, run.choice.params, options, progress);
    run.choice.judged = pnf::detail::too_wide_heading(root.samples, root.fit_points, root.cloud_points) +
                        pnf::detail::judged_outcome(0, 0);
    return run;
  }
  const std::vector<FilterParams> checked_settings = pnf::detail::held_out_settings(run.choice, root.fit_points);
  std::vector<Vec3> checked(held_out ? local.size() : 0), checked_trial(held_out ? local.size() : 0);
  double checked_best = std::numeric_limits<double>::infinity();
  FilterParams checked_params;
  int checked_passes = 0;
  DistributedSummary checked_summary;
  std::string checked_text;
  // The check's part of a run of its `setting` (held_out_settings' number), after the run.
  auto checked_run = [&](const detail::PassJudging& judging, const FilterParams& params, int setting,
                         const DistributedSummary& summary) {
    if (checked_text.empty()) {
      checked_text = pnf::detail::held_out_heading(judging.checked_samples, judging.checked_by_pass[0]);
    }
    checked_text += pnf::detail::judged_candidate(std::size_t(setting), params, judging.checked_by_pass);
    if (judging.checked_best_pass > 0) {
      checked.swap(checked_trial);
      checked_best = judging.checked_by_pass[std::size_t(judging.checked_best_pass)];
      checked_params = params;
      checked_passes = judging.checked_best_pass;
      checked_summary = summary;
    }
  };
  auto checking = [&](detail::PassJudging& judging) {
    judging.check = true;
    judging.checked_best_before = checked_best;
    judging.checked_out = MutableVec3ArrayView(checked_trial);
  };
  detail::PassJudging first;  // the rule's setting's judging: the judge's numbers, as every rank has them
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    // Where the judge's fits are too wide, only the held-out check runs (as one process runs it).
    if (too_wide && !(held_out && c == 0)) continue;
    FilterParams params = candidates[c];
    params.iterations = pnf::detail::judged_pass_budget(params, run.choice, root.fit_points);
    detail::PassJudging judging;
    judging.root = rank == 0 ? &root : nullptr;
    judging.budget = too_wide ? 0 : params.iterations;
    judging.input_noise_deg = input_noise;
    if (c > 0) judging.best_before = best_rms;
    if (held_out && c == 0) checking(judging);  // held_out_settings' first is this one
    const DistributedSummary summary =
        detail::improve_normals(comm, local, MutableVec3ArrayView(trial), params, options, progress, &judging);
    const double rms = judging.best_pass > 0 ? judging.rms_by_pass[std::size_t(judging.best_pass)]
                                             : pnf::detail::rms_to_beat(judging.rms_by_pass[0], judging.error_deg);
    if (c == 0) {
      first = judging;
      judged = too_wide ? pnf::detail::too_wide_heading(root.samples, root.fit_points, root.cloud_points)
                        : pnf::detail::judged_heading(judging.rms_by_pass[0], judging.own_error_deg, judging.error_deg,
                                                      judging.samples, judging.fit_points, judging.under_support);
    }
    if (!too_wide) {
      judged += pnf::detail::judged_candidate(c, params, judging.rms_by_pass) +
                pnf::detail::judged_budget_note(candidates[c], params.iterations);
    }
    if (held_out && c == 0) checked_run(judging, params, 0, summary);
    if (c == 0 || rms < best_rms) {
      best_candidate = c;
      run.passes_kept = judging.best_pass;
      best_rms = rms;
      best.swap(trial);
      run.summary = summary;
    }
    run.judged_rms_deg.insert(run.judged_rms_deg.end(), judging.rms_by_pass.begin() + 1, judging.rms_by_pass.end());
  }
  const pnf::detail::Fallback fallback =
      pnf::detail::fallback_of(run.choice, first.plane_fits, first.fit_points, first.rms_by_pass[0], first.error_deg);
  if (run.passes_kept == 0 && fallback.candidate > 0) {
    detail::PassJudging judging;
    judging.root = rank == 0 ? &root : nullptr;
    judging.budget = too_wide ? 0 : fallback.params.iterations;
    judging.input_noise_deg = input_noise;
    judging.fallback = fallback;
    // With the held-out check, the fallback's setting (held_out_settings' second) runs on to the
    // check's budget; the judge scores its first passes (fallback_pass_budget).
    FilterParams params = fallback.params;
    if (held_out) {
      params.iterations = checked_settings[1].iterations;
      checking(judging);
    }
    const DistributedSummary summary =
        detail::improve_normals(comm, local, MutableVec3ArrayView(trial), params, options, progress, &judging);
    if (!too_wide) judged += pnf::detail::judged_fallback(fallback, judging.rms_by_pass);
    if (held_out) checked_run(judging, params, 1, summary);
    if (judging.best_pass > 0) {
      best_candidate = fallback.candidate;
      run.passes_kept = judging.best_pass;
      best.swap(trial);
      run.summary = summary;
    }
    run.judged_rms_deg.insert(run.judged_rms_deg.end(), judging.rms_by_pass.begin() + 1, judging.rms_by_pass.end());
  }
  // The check's text only where it decided: where the judge kept a pass, the check stopped.
  if (run.passes_kept == 0 && held_out) judged += checked_text;
  if (run.passes_kept == 0 && checked_passes > 0) {
    best.swap(checked);
    best_candidate = pnf::detail::kHeldOutCandidate;
    run.passes_kept = checked_passes;
    run.summary = checked_summary;
  }
  for (std::size_t i = 0; i < local.size(); ++i) normals_out.set(i, best[i]);
  judged += pnf::detail::judged_outcome(best_candidate, run.passes_kept);
  if (run.passes_kept > 0) {
    run.choice.params = best_candidate == pnf::detail::kHeldOutCandidate    ? checked_params
                        : best_candidate >= pnf::detail::kFallbackCandidate ? fallback.params
                                                                            : candidates[best_candidate];
  }
  run.choice.judged = judged;
  run.choice.params.iterations = run.passes_kept;
  return run;
}

}  // namespace pnf::mpi
