// pnf::mpi::improve_normals: partition, mean radius, halo, the engine on each rank's part, and
// the normals back to their ranks, with the ranks agreeing on failures before each step.
#include "pnf/mpi.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "agreement.hpp"
#include "auto/judged_passes.hpp"
#include "device_choice.hpp"
#include "filter_engine.hpp"
#include "filter_plan.hpp"
#include "halo.hpp"
#include "judged_run.hpp"
#include "mean_radius_mpi.hpp"
#include "own_comm.hpp"
#include "partition.hpp"
#include "rank_cloud_check.hpp"

namespace pnf::mpi {
namespace {

// A distributed run's judged passes (improve_normals_auto across ranks), scored as one process
// scores them: rank 0 holds the judge over the whole cloud (RootJudge); after each pass every
// rank sends it its points' new normals (with their global ids, the rows of the whole cloud),
// rank 0 scores them and every rank gets the score, so all take one process's decisions. Each
// rank keeps its own points' normals of the best pass so far (the input first).
class JudgedPasses {
 public:
  JudgedPasses(MPI_Comm comm, detail::PassJudging& judging, const CloudView& view,
               const std::vector<std::uint64_t>& gids, std::size_t owned, std::size_t total)
      : comm_(comm), judging_(judging), owned_(owned), total_(total) {
    MPI_Comm_rank(comm_, &rank_);
    best_ = pnf::detail::unit_rows(view.normals);
    best_.resize(3 * owned);  // the owned rows come first
    gather_counts(gids);
    if (judging_.probing) return;
    if (judging_.stein) {  // rms_by_pass holds the input's estimate
      judging_.best_pass = 0;
      best_rms_ = judging_.to_beat;
      return;
    }
    double numbers[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    if (judging_.root) {
      const pnf::detail::SurfaceJudge& judge = judging_.root->judge;
      const double* input = judging_.root->input_normals.data();
      const pnf::detail::SurfaceJudge::Sums sums = judge.input_sums(input);
      numbers[0] = sums.rms_deg();
      numbers[1] = sums.own_error_deg();
      numbers[2] = double(judge.scored());
      numbers[3] = double(judge.size());
      numbers[4] = double(judge.under_support());
      numbers[5] = double(judge.plane_fits());
      if (judging_.check) {
        numbers[6] = judging_.root->held_out.score(input).disagreement_deg;
        numbers[7] = double(judging_.root->held_out.size());
      }
    }
    detail::check_mpi(MPI_Bcast(numbers, 8, MPI_DOUBLE, 0, comm_), "MPI_Bcast");
    judging_.rms_by_pass.assign(1, numbers[0]);
    judging_.own_error_deg = numbers[1];
    judging_.error_deg = pnf::detail::judge_error_deg(numbers[0], numbers[1], judging_.input_noise_deg);
    judging_.fit_points = int(numbers[2]);
    judging_.samples = std::size_t(numbers[3]);
    judging_.under_support = int(numbers[4]);
    judging_.plane_fits = int(numbers[5]);
    judging_.checked_by_pass.assign(1, numbers[6]);
    judging_.checked_samples = std::size_t(numbers[7]);
    judging_.checked_best_pass = 0;
    judging_on_ = judging_.budget > 0;
    checking_on_ = judging_.check;
    checked_best_ = std::min(judging_.checked_best_before, numbers[6]);
    // A pass must beat the input by more than the judge's error explains (a fallback's bar is
    // its own: judged_passes.hpp).
    best_rms_ =
        std::min(judging_.best_before, judging_.fallback.candidate > 0
                                           ? judging_.fallback.to_beat
                                           : pnf::detail::rms_to_beat(judging_.rms_by_pass[0], judging_.error_deg));
    judging_.best_pass = 0;
  }

  void after_pass(const std::vector<double>& owned_normals) {
    if (judging_.probing) {
      const std::vector<double> whole = gathered_on_root(owned_normals);
      if (judging_.root) judging_.samples_by_pass.push_back(judging_.root->stein.at_samples(whole.data()));
      ++judging_.passes;
      return;
    }
    if (judging_.stein) {
      estimated_on_root(owned_normals);
      return;
    }
    ++pass_;
    const Scores scores = scored_on_root(owned_normals);
    if (judging_on_) {
      judging_.rms_by_pass.push_back(scores.rms);
      if (scores.rms < judging_.rms_by_pass[std::size_t(best_here_)]) best_here_ = pass_;
      if (scores.rms < best_rms_) {
        best_rms_ = scores.rms;
        judging_.best_pass = pass_;
        best_.assign(owned_normals.begin(), owned_normals.begin() + std::ptrdiff_t(3 * owned_));
      }
      judging_on_ = pass_ < judging_.budget &&
                    !pnf::detail::judged_passes_end(judging_.rms_by_pass, best_here_, best_rms_, judging_.budget);
    }
    checking_on_ = checking_on_ && judging_.best_pass == 0;
    if (checking_on_) {
      judging_.checked_by_pass.push_back(scores.disagreement);
      if (scores.disagreement < judging_.checked_by_pass[std::size_t(checked_here_)]) checked_here_ = pass_;
      if (checked_candidate(scores) && !pnf::detail::judge_vetoes(scores.rms, judging_.rms_by_pass[0])) {
        checked_best_ = scores.disagreement;
        judging_.checked_best_pass = pass_;
        checked_.assign(owned_normals.begin(), owned_normals.begin() + std::ptrdiff_t(3 * owned_));
      }
      checking_on_ = !pnf::detail::judged_passes_end(judging_.checked_by_pass, checked_here_, pnf::detail::kNoBar, 0);
    }
  }
  bool enough() const {
    if (judging_.probing) return false;
    if (judging_.stein) {
      return pnf::detail::judged_passes_end(judging_.rms_by_pass, best_here_, pnf::detail::kNoBar, judging_.budget) ||
             int(judging_.rms_by_pass.size()) - 1 >= judging_.probed->passes;
    }
    return !judging_on_ && !checking_on_;
  }
  const std::vector<double>& best_normals() const { return best_; }
  // The held-out check's pass's normals (this rank's owned rows); empty where it kept none.
  const std::vector<double>& checked_normals() const { return checked_; }

 private:
  // Rank 0 learns where each rank's rows go in the whole cloud (once).
  void gather_counts(const std::vector<std::uint64_t>& gids) {
    int ranks = 1;
    MPI_Comm_size(comm_, &ranks);
    const int mine = int(owned_);
    counts_.assign(std::size_t(ranks), 0);
    detail::check_mpi(MPI_Gather(&mine, 1, MPI_INT, counts_.data(), 1, MPI_INT, 0, comm_), "MPI_Gather");
    displacements_.assign(std::size_t(ranks), 0);
    for (int r = 1; r < ranks; ++r)
      displacements_[std::size_t(r)] = displacements_[std::size_t(r) - 1] + counts_[std::size_t(r) - 1];
    all_gids_.resize(rank_ == 0 ? total_ : 0);
    std::vector<unsigned long long> my_gids(gids.begin(), gids.begin() + std::ptrdiff_t(owned_));
    detail::check_mpi(MPI_Gatherv(my_gids.data(), mine, MPI_UNSIGNED_LONG_LONG, all_gids_.data(), counts_.data(),
                                  displacements_.data(), MPI_UNSIGNED_LONG_LONG, 0, comm_),
                      "MPI_Gatherv");
  }

  // The judge's RMS of the whole cloud's normals after a pass and the held-out check's score,
  // each where it still scores, from rank 0, on every rank.
  struct Scores {
    double rms = 0, disagreement = 0, gain_z = 0;
  };
  // The judge scores a pass it judges, and one the check would keep, for its veto.
  Scores scored_on_root(const std::vector<double>& owned_normals) {
    const std::vector<double> whole = gathered_on_root(owned_normals);
    Scores scores;
    if (judging_.root && checking_on_) {
      const pnf::detail::HeldOutPlanes::Score score = judging_.root->held_out.score(whole.data());
      scores.disagreement = score.disagreement_deg;
      scores.gain_z = score.gain_z;
    }
    if (judging_.root && (judging_on_ || checked_candidate(scores))) {
      scores.rms = judging_.root->judge.rms_deg(whole.data());
    }
    double numbers[3] = {scores.rms, scores.disagreement, scores.gain_z};
    detail::check_mpi(MPI_Bcast(numbers, 3, MPI_DOUBLE, 0, comm_), "MPI_Bcast");
    return {numbers[0], numbers[1], numbers[2]};
  }
  // Whether the check would keep a pass of these scores, but for the judge's veto.
  bool checked_candidate(const Scores& scores) const {
    return checking_on_ && scores.disagreement < checked_best_ && scores.gain_z >= pnf::detail::kHeldOutMinGainZ;
  }

  // Where Stein's estimate decides: the pass's estimate (from rank 0, on every rank), and where it
  // is the lowest so far, this rank's normals kept.
  void estimated_on_root(const std::vector<double>& owned_normals) {
    const std::vector<double> whole = gathered_on_root(owned_normals);
    const int pass = int(judging_.rms_by_pass.size());
    double estimate = 0;
    if (judging_.root) {
      const pnf::detail::SteinRisk& stein = judging_.root->stein;
      estimate =
          stein.risk_deg(stein.at_samples(whole.data()), judging_.probed->samples_by_pass[std::size_t(pass) - 1]);
    }
    detail::check_mpi(MPI_Bcast(&estimate, 1, MPI_DOUBLE, 0, comm_), "MPI_Bcast");
    judging_.rms_by_pass.push_back(estimate);
    if (estimate < judging_.rms_by_pass[std::size_t(best_here_)]) best_here_ = pass;
    if (estimate < best_rms_) {
      best_rms_ = estimate;
      judging_.best_pass = pass;
      best_.assign(owned_normals.begin(), owned_normals.begin() + std::ptrdiff_t(3 * owned_));
    }
  }

  // The whole cloud's normals after a pass on rank 0 (empty elsewhere), in the whole cloud's rows.
  std::vector<double> gathered_on_root(const std::vector<double>& owned_normals) {
    std::vector<int> counts3(counts_.size()), displacements3(counts_.size());
    for (std::size_t r = 0; r < counts_.size(); ++r) {
      counts3[r] = 3 * counts_[r];
      displacements3[r] = 3 * displacements_[r];
    }
    std::vector<double> gathered(rank_ == 0 ? 3 * total_ : 0);
    detail::check_mpi(MPI_Gatherv(owned_normals.data(), int(3 * owned_), MPI_DOUBLE, gathered.data(), counts3.data(),
                                  displacements3.data(), MPI_DOUBLE, 0, comm_),
                      "MPI_Gatherv");
    std::vector<double> whole;
    if (judging_.root) {
      whole.resize(3 * total_);
      for (std::size_t k = 0; k < total_; ++k) {
        for (int c = 0; c < 3; ++c) whole[3 * all_gids_[k] + std::size_t(c)] = gathered[3 * k + std::size_t(c)];
      }
    }
    return whole;
  }

  MPI_Comm comm_;
  detail::PassJudging& judging_;
  std::size_t owned_, total_;
  int rank_ = 0;
  std::vector<int> counts_, displacements_;   // rank 0: each rank's points, and where they start
  std::vector<unsigned long long> all_gids_;  // rank 0: the global id of each gathered row
  std::vector<double> best_;
  double best_rms_ = 0;  // to beat: the input's bar, then the best kept pass's
  int best_here_ = 0;    // the lowest judged pass, the input included, for the end of the passes
  int pass_ = 0;
  bool judging_on_ = false, checking_on_ = false;  // whether the judge, the held-out check still score
  std::vector<double> checked_;                    // the check's pass kept, this rank's rows
  double checked_best_ = 0;                        // the disagreement to beat
  int checked_here_ = 0;                           // the check's lowest pass, the input included
};

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

template <typename T>
void reduce_min_max(MPI_Comm comm, T value, T& low, T& high) {
  unsigned long long v[2] = {static_cast<unsigned long long>(value), ~static_cast<unsigned long long>(value)};
  MPI_Allreduce(MPI_IN_PLACE, v, 2, MPI_UNSIGNED_LONG_LONG, MPI_MAX, comm);
  high = static_cast<T>(v[0]);
  low = static_cast<T>(~v[1]);
}

unsigned long long sum_over(MPI_Comm comm, unsigned long long value) {
  MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm);
  return value;
}

// The twin's normals of the points this rank owns, in `owned`'s order: moved to their owners as
// the points were (the partition follows the positions alone), then matched by global id (ties
// of the curve order may fall otherwise among points at one place). Collective.
std::vector<double> owned_twin_rows(MPI_Comm comm, const CloudView& local, const Vec3ArrayView& twin_normals,
                                    const detail::GlobalFrame& frame, const detail::OwnedPoints& owned,
                                    std::size_t& moved) {
  std::size_t twin_moved = 0;
  const detail::OwnedPoints twin =
      detail::distribute(comm, CloudView(local.positions, twin_normals), frame, twin_moved);
  moved += twin_moved;
  auto by_gid = [](const std::vector<std::uint64_t>& gids) {
    std::vector<std::size_t> order(gids.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return gids[a] < gids[b]; });
    return order;
  };
  const std::vector<std::size_t> mine = by_gid(owned.gids), theirs = by_gid(twin.gids);
  if (theirs.size() != mine.size()) {
    throw std::logic_error("internal error: this rank owns " + std::to_string(mine.size()) + " points of the run and " +
                           std::to_string(theirs.size()) + " of its twin");
  }
  std::vector<double> rows(3 * owned.size());
  for (std::size_t j = 0; j < mine.size(); ++j) {
    if (owned.gids[mine[j]] != twin.gids[theirs[j]]) {
      throw std::logic_error("internal error: the twin run's points went to other ranks than the run's (global id " +
                             std::to_string(owned.gids[mine[j]]) + ")");
    }
    for (int c = 0; c < 3; ++c) rows[3 * mine[j] + std::size_t(c)] = twin.normals[3 * theirs[j] + std::size_t(c)];
  }
  return rows;
}

}  // namespace

DistributedSummary detail::improve_normals(MPI_Comm caller_comm, const CloudView& local,
                                           MutableVec3ArrayView normals_out, const FilterParams& params,
                                           const FilterOptions& options, const ProgressCallback& progress,
                                           PassJudging* judging, const TwinJudging* twin) {
  detail::OwnComm own_comm(caller_comm);
  const MPI_Comm comm = own_comm.get();
  const detail::Agreement agree(comm);
  DistributedSummary summary;
  summary.ranks = agree.size();

  // Everything that can be refused is refused before any point moves.
  agree.run([&] {
    detail::check_rank_cloud(comm, local);  // its collective first, before anything can throw
    params.validate();
    options.validate();
    if (normals_out.count != local.size()) {
      throw Error(ErrorCode::invalid_argument, "the output normals hold " + std::to_string(normals_out.count) +
                                                   " rows for " + std::to_string(local.size()) + " points");
    }
  });
  FilterOptions resolved;
  std::unique_ptr<pnf::detail::FilterBackend> backend;
  agree.run([&] { backend = detail::make_rank_backend(comm, options, resolved); });

  auto t = Clock::now();
  const detail::GlobalFrame frame = detail::global_frame(comm, local.positions);
  std::size_t moved = 0;
  detail::OwnedPoints owned = detail::distribute(comm, local, frame, moved);
  std::vector<double> twin_normals;  // the view's rows: owned, then (below) the halo's
  if (twin) agree.run([&] { twin_normals = owned_twin_rows(comm, local, twin->normals, frame, owned, moved); });
  summary.points = owned.total;
  summary.partition_seconds = seconds_since(t);
  if (owned.total == 0) return summary;  // as one process: an empty cloud, an empty result

  t = Clock::now();
  RadiusSource source = RadiusSource::not_used;
  double mean_radius = 0;
  Vec3 origin = {0, 0, 0};
  agree.run([&] {
    origin = detail::sample_median(comm, owned);
    mean_radius = detail::resolve_mean_radius(comm, local, owned, frame, origin, params, source);
  });
  summary.radius_seconds = seconds_since(t);

  // The halo: every other rank's point within the lists' reach of one of ours.
  t = Clock::now();
  const pnf::detail::FilterPlan filter_plan = pnf::detail::make_filter_plan(params, {mean_radius, source});
  const double reach = filter_plan.reach;
  const std::size_t n = owned.size();
  detail::HaloPlan plan;
  {
    const auto lists = detail::points_near(comm, owned.positions, owned.positions, reach, frame);
    std::vector<double> halo_positions, halo_normals;
    plan.build(comm, owned, lists, halo_positions, halo_normals);
    // Own points first, then the halo: the engine's view of a distributed part.
    owned.positions.insert(owned.positions.end(), halo_positions.begin(), halo_positions.end());
    owned.normals.insert(owned.normals.end(), halo_normals.begin(), halo_normals.end());
  }
  moved += plan.bytes_moved();
  summary.halo_seconds = seconds_since(t);

  FilterParams part_params = params;
  if (params.units == Units::radius) part_params.mean_radius = mean_radius;
  pnf::detail::DistributedPart part;
  part.owned = n;
  // One process's curve and centre, so each point's list and sums are one process's.
  part.has_whole_frame = true;
  part.whole_curve = frame.morton;
  part.whole_centre = origin;
  part.exchange_halo = [&](const std::vector<double>& owned_normals, std::vector<double>& halo) {
    agree.check();  // a rank that failed in its pass ends the run here, on every rank
    plan.exchange(owned_normals, halo);
  };
  part.job_sum = [&](double* values, int count) {
    agree.check();  // a rank that failed before the refusals ends the run here, on every rank
    detail::check_mpi(MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_DOUBLE, MPI_SUM, comm), "MPI_Allreduce");
  };
  part.sum_over_processes = [&](double* values, int count) {
    detail::check_mpi(MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_DOUBLE, MPI_SUM, comm), "MPI_Allreduce");
  };
  const std::size_t rows = n + plan.halo_points();
  const CloudView view(Vec3ArrayView(owned.positions.data(), rows), Vec3ArrayView(owned.normals.data(), rows));
  std::vector<double> new_normals(3 * n);
  // The twin's part: its halo from their owners now and after each of its passes, each pass
  // judged (probed) as one process's twin.
  pnf::detail::DistributedPart twin_part = part;
  std::unique_ptr<JudgedPasses> twin_judged;
  if (twin) {
    std::vector<double> halo;
    plan.exchange(twin_normals, halo);
    twin_normals.insert(twin_normals.end(), halo.begin(), halo.end());
    const CloudView twin_view(view.positions, Vec3ArrayView(twin_normals.data(), rows));
    agree.run([&] {
      twin_judged = std::make_unique<JudgedPasses>(comm, *twin->judging, twin_view, owned.gids, n, owned.total);
    });
    twin_part.exchange_halo = [&](const std::vector<double>& owned_normals, std::vector<double>& halo_normals) {
      agree.check();
      plan.exchange(owned_normals, halo_normals);
      twin_judged->after_pass(owned_normals);
    };
    twin_part.ends_passes = [&] { return twin_judged->enough(); };
  }
  const pnf::detail::TwinRun twin_run{Vec3ArrayView(twin_normals.data(), twin ? rows : 0), &twin_part};
  std::unique_ptr<JudgedPasses> judged;
  if (judging) {
    agree.run([&] { judged = std::make_unique<JudgedPasses>(comm, *judging, view, owned.gids, n, owned.total); });
    part.exchange_halo = [&](const std::vector<double>& owned_normals, std::vector<double>& halo) {
      agree.check();
      plan.exchange(owned_normals, halo);
      judged->after_pass(owned_normals);
    };
    part.ends_passes = [&] { return judged->enough(); };
  }
  agree.run([&] {
    summary.local = pnf::detail::run_filter(*backend, resolved, view, MutableVec3ArrayView(new_normals.data(), n),
                                            part_params, progress, &part, twin ? &twin_run : nullptr);
  });
  std::vector<double> checked_normals;
  if (judged) {
    new_normals = judged->best_normals();
    checked_normals = judged->checked_normals();
  }
  backend.reset();
  summary.local.mean_radius = filter_plan.radius.value;
  summary.local.radius_source = filter_plan.radius.source;
  summary.local.sigma_f = filter_plan.sigma_f;
  summary.local.sigma_g = filter_plan.sigma_g;

  reduce_min_max(comm, n, summary.owned_min, summary.owned_max);
  reduce_min_max(comm, plan.halo_points(), summary.halo_min, summary.halo_max);
  summary.neighbour_pairs = sum_over(comm, summary.local.neighbour_pairs);
  summary.halo_bytes_per_pass = sum_over(comm, plan.bytes_sent_per_pass());
  summary.messages_per_pass = sum_over(comm, plan.messages_per_pass());
  summary.moved_bytes = sum_over(comm, moved);
  double phases[3] = {summary.partition_seconds, summary.radius_seconds, summary.halo_seconds};
  MPI_Allreduce(MPI_IN_PLACE, phases, 3, MPI_DOUBLE, MPI_MAX, comm);
  summary.partition_seconds = phases[0];
  summary.radius_seconds = phases[1];
  summary.halo_seconds = phases[2];
  // Every rank ran the same passes (the stop rule's sums are global); a rank with no points
  // reports zero seconds for each.
  summary.pass_seconds = summary.local.pass_seconds;
  if (!summary.pass_seconds.empty()) {
    MPI_Allreduce(MPI_IN_PLACE, summary.pass_seconds.data(), int(summary.pass_seconds.size()), MPI_DOUBLE, MPI_MAX,
                  comm);
  }

  detail::return_normals(comm, owned, new_normals, normals_out);
  // The held-out check's pass, where it kept one (the same on every rank).
  if (judging && judging->check && judging->checked_best_pass > 0) {
    detail::return_normals(comm, owned, checked_normals, judging->checked_out);
  }
  return summary;
}

DistributedSummary improve_normals(MPI_Comm comm, const CloudView& local, MutableVec3ArrayView normals_out,
                                   const FilterParams& params, const FilterOptions& options,
                                   const ProgressCallback& progress) {
  return detail::improve_normals(comm, local, normals_out, params, options, progress, nullptr);
}

}  // namespace pnf::mpi
