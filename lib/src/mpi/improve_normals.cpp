// pnf::mpi::improve_normals: partition, mean radius, halo, the engine on each rank's part, and
// the normals back to their ranks, with the ranks agreeing on failures before each step.
#include "pnf/mpi.hpp"

#include <algorithm>
#include <chrono>
#include <memory>

#include "agreement.hpp"
#include "device_choice.hpp"
#include "filter_engine.hpp"
#include "halo.hpp"
#include "mean_radius_mpi.hpp"
#include "own_comm.hpp"
#include "partition.hpp"
#include "pnf_common.h"
#include "rank_cloud_check.hpp"

namespace pnf::mpi {
namespace {

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

DistributedSummary improve_normals(MPI_Comm caller_comm, const CloudView& local, MutableVec3ArrayView normals_out,
                                   const FilterParams& params, const FilterOptions& options,
                                   const ProgressCallback& progress) {
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
  const double scale = params.units == Units::radius ? mean_radius : 1.0;
  const double reach = PNF_SUPPORT_IN_SIGMA_F * params.sigma_f * scale;
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
  agree.run([&] {
    summary.local = pnf::detail::run_filter(*backend, resolved, view, MutableVec3ArrayView(new_normals.data(), n),
                                            part_params, progress, &part);
  });
  backend.reset();
  summary.local.mean_radius = mean_radius;
  summary.local.radius_source = source;
  summary.local.sigma_f = params.sigma_f * scale;
  summary.local.sigma_g = params.sigma_g * scale;

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

}  // namespace pnf::mpi
