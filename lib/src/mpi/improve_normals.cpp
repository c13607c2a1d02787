// pnf::mpi::improve_normals: partition, mean radius, halo, the engine on each rank's part, and
// the normals back to their ranks, with the ranks agreeing on failures before each step.
#include "pnf/mpi.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "agreement.hpp"
#include "device_choice.hpp"
#include "filter_engine.hpp"
#include "filter_plan.hpp"
#include "halo.hpp"
#include "geometry.hpp"
#include "auto/judged_passes.hpp"
#include "judged_run.hpp"
#include "mean_radius_mpi.hpp"
#include "own_comm.hpp"
#include "partition.hpp"
#include "rank_cloud_check.hpp"
#include "spatial/spatial_index.hpp"

namespace pnf::mpi {
namespace {

// A distributed run's judged passes (improve_normals_auto across ranks): each rank judges the
// samples among its own points, against its points and halo, and the ranks' sums are added, so
// every rank sees the same RMS and takes the same decisions. Each keeps its own points' normals
// of the best pass so far (the input first).
class JudgedPasses {
 public:
  JudgedPasses(MPI_Comm comm, detail::PassJudging& judging, const CloudView& view, std::size_t owned,
               std::size_t total)
      : comm_(comm), judging_(judging), owned_(owned) {
    std::vector<double> positions(3 * view.size());
    for (std::size_t i = 0; i < view.size(); ++i) {
      const Vec3 p = view.positions.at(i);
      for (int c = 0; c < 3; ++c) positions[3 * i + c] = p[c];
    }
    const std::size_t samples =
        total > 0 ? (judging.geometry.samples * owned + total - 1) / total : 0;  // this rank's share
    const pnf::detail::SpatialIndex index(std::move(positions), pnf::detail::SpatialIndex::Layout::any_order);
    judge_ = pnf::detail::SurfaceJudge(index, samples, judging.geometry.neighbours, judging.geometry.width, owned);
    best_.resize(3 * owned);
    for (std::size_t i = 0; i < owned; ++i) {
      const Vec3 v = view.normals.at(i);
      const double length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      for (int c = 0; c < 3; ++c) best_[3 * i + c] = v[c] / length;
    }
    const pnf::detail::SurfaceJudge::Sums input = chosen_scale_sums(judging.geometry);
    double sums[5] = {input.squared, input.disagreement, input.variance, input.inner_variance, double(judge_.size())};
    detail::check_mpi(MPI_Allreduce(MPI_IN_PLACE, sums, 5, MPI_DOUBLE, MPI_SUM, comm_), "MPI_Allreduce");
    const pnf::detail::SurfaceJudge::Sums all{sums[0], sums[1], sums[2], sums[3]};
    const double to_degrees = 180 / pnf::geometry::kPi;
    judging_.rms_by_pass.assign(1, sums[4] > 0 ? std::sqrt(sums[0] / sums[4]) * to_degrees : 0.0);
    judging_.own_error_deg = sums[4] > 0 ? std::sqrt(all.own_error_squared() / sums[4]) * to_degrees : 0.0;
    judging_.fit_points = judge_.scored();
    // A pass must beat the input by more than the judge's own error explains.
    best_rms_ = pnf::detail::rms_to_beat(judging_.rms_by_pass[0], judging_.own_error_deg);
    judging_.best_pass = 0;
  }

  void after_pass(const std::vector<double>& owned_normals) {
    const double rms = summed_rms(owned_normals);
    judging_.rms_by_pass.push_back(rms);
    const int pass = int(judging_.rms_by_pass.size()) - 1;
    if (rms < judging_.rms_by_pass[std::size_t(best_here_)]) best_here_ = pass;
    if (rms < best_rms_) {
      best_rms_ = rms;
      judging_.best_pass = pass;
      best_.assign(owned_normals.begin(), owned_normals.begin() + std::ptrdiff_t(3 * owned_));
    }
  }
  bool enough() const { return int(judging_.rms_by_pass.size()) - 1 - best_here_ >= judging_.passes_past_best; }
  const std::vector<double>& best_normals() const { return best_; }

 private:
  // The judge's scale as one process's choose_scale takes it, on the ranks' added sums (every rank
  // decides alike), and this rank's sums of the input at that scale.
  pnf::detail::SurfaceJudge::Sums chosen_scale_sums(const pnf::detail::JudgeGeometry& geometry) {
    using Sums = pnf::detail::SurfaceJudge::Sums;
    std::vector<int> scales = pnf::detail::SurfaceJudge::scales_of(geometry.neighbours);
    if (!geometry.quarter_allowed) scales.resize(1);
    auto local_sums = [&](int points) {
      judge_.score_with(points);
      return judge_.empty() ? Sums{} : judge_.sums(best_.data());
    };
    const Sums whole = local_sums(scales[0]);
    if (scales.size() < 2) return whole;
    const Sums quarter = local_sums(scales[1]);
    double added[8] = {whole.squared,   whole.disagreement,   whole.variance,   whole.inner_variance,
                       quarter.squared, quarter.disagreement, quarter.variance, quarter.inner_variance};
    detail::check_mpi(MPI_Allreduce(MPI_IN_PLACE, added, 8, MPI_DOUBLE, MPI_SUM, comm_), "MPI_Allreduce");
    if (pnf::detail::SurfaceJudge::quarter_is_better({added[0], added[1], added[2], added[3]},
                                                     {added[4], added[5], added[6], added[7]})) {
      return quarter;
    }
    judge_.score_with(scales[0]);
    return whole;
  }

  double summed_rms(const std::vector<double>& normals) const {
    double sums[2] = {judge_.empty() ? 0.0 : judge_.sum_squared(normals.data()), double(judge_.size())};
    detail::check_mpi(MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, comm_), "MPI_Allreduce");
    return sums[1] > 0 ? std::sqrt(sums[0] / sums[1]) * 180 / pnf::geometry::kPi : 0.0;
  }

  MPI_Comm comm_;
  detail::PassJudging& judging_;
  std::size_t owned_;
  pnf::detail::SurfaceJudge judge_;
  std::vector<double> best_;
  double best_rms_ = 0;  // to beat: the input's bar, then the best kept pass's
  int best_here_ = 0;    // the lowest judged pass, the input included, for the end of the passes
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

}  // namespace

DistributedSummary detail::improve_normals(MPI_Comm caller_comm, const CloudView& local,
                                           MutableVec3ArrayView normals_out, const FilterParams& params,
                                           const FilterOptions& options, const ProgressCallback& progress,
                                           PassJudging* judging) {
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
  summary.points = owned.total;
  summary.partition_seconds = seconds_since(t);
  if (owned.total == 0) return summary;  // as one process: an empty cloud, an empty result

  t = Clock::now();
  RadiusSource source = RadiusSource::not_used;
  double mean_radius = 0;
  agree.run([&] { mean_radius = detail::resolve_mean_radius(comm, local, owned, frame, params, source); });
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
  part.whole_centre = frame.centre();
  part.exchange_halo = [&](const std::vector<double>& owned_normals, std::vector<double>& halo) {
    agree.check();  // a rank that failed in its pass ends the run here, on every rank
    plan.exchange(owned_normals, halo);
  };
  part.sum_over_processes = [&](double* values, int count) {
    detail::check_mpi(MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_DOUBLE, MPI_SUM, comm), "MPI_Allreduce");
  };
  const std::size_t rows = n + plan.halo_points();
  const CloudView view(Vec3ArrayView(owned.positions.data(), rows), Vec3ArrayView(owned.normals.data(), rows));
  std::vector<double> new_normals(3 * n);
  std::unique_ptr<JudgedPasses> judged;
  if (judging) {
    agree.run([&] { judged = std::make_unique<JudgedPasses>(comm, *judging, view, n, owned.total); });
    part.exchange_halo = [&](const std::vector<double>& owned_normals, std::vector<double>& halo) {
      agree.check();
      plan.exchange(owned_normals, halo);
      judged->after_pass(owned_normals);
    };
    part.ends_passes = [&] { return judged->enough(); };
  }
  agree.run([&] {
    summary.local = pnf::detail::run_filter(*backend, resolved, view, MutableVec3ArrayView(new_normals.data(), n),
                                            part_params, progress, &part);
  });
  if (judged) new_normals = judged->best_normals();
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
  return summary;
}

DistributedSummary improve_normals(MPI_Comm comm, const CloudView& local, MutableVec3ArrayView normals_out,
                                   const FilterParams& params, const FilterOptions& options,
                                   const ProgressCallback& progress) {
  return detail::improve_normals(comm, local, normals_out, params, options, progress, nullptr);
}

}  // namespace pnf::mpi
