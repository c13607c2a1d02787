// pnf::mpi::choose_filter_params: --auto across the ranks (pnf/mpi.hpp).
#include <cmath>
#include <string>
#include <vector>

#include "agreement.hpp"
#include "mean_radius_mpi.hpp"
#include "judged_run.hpp"
#include "own_comm.hpp"
#include "partition.hpp"
#include "pnf/auto_params.hpp"
#include "pnf/mpi.hpp"

namespace pnf::mpi {
namespace {

// Each rank estimates the data on its own slice (a few hundred fitted samples each, so every
// rank's part of the model has its say); every rank gets all the estimates and pools them
// (pnf::pool_estimates). A slice that cannot be estimated (too few points, or all on a line)
// counts only its points; when that is every slice, each rank says why its own failed.
DataEstimate pooled_estimate(MPI_Comm comm, const CloudView& local) {
  DataEstimate e;
  e.points = local.size();
  std::string why_not;
  try {
    if (local.size() > 0) e = estimate_data(local);
  } catch (const Error& error) {
    e = DataEstimate{};
    e.points = local.size();
    why_not = error.what();
  }
  // Every field as a double (all of them are exact in one: counts stay far below 2^53).
  constexpr int kFields = 18;
  const double mine[kFields] = {double(e.points),
                                double(e.samples),
                                e.mean_radius,
                                double(int(e.radius_source)),
                                e.area_spacing,
                                e.position_noise,
                                e.normal_noise_deg,
                                double(e.fit_neighbours),
                                e.fit_radius,
                                e.feature_share,
                                e.crease_length,
                                double(e.edge_samples),
                                double(e.feature_samples),
                                e.curved_share,
                                e.normal_error_correlation,
                                e.normal_position_coupling,
                                e.crease_sharpness,
                                e.normal_crease_length};
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  std::vector<double> all(std::size_t(ranks) * kFields);
  MPI_Allgather(mine, kFields, MPI_DOUBLE, all.data(), kFields, MPI_DOUBLE, comm);
  std::vector<DataEstimate> parts(static_cast<std::size_t>(ranks));
  bool any_samples = false;
  std::size_t points = 0;
  for (int r = 0; r < ranks; ++r) {
    const double* f = all.data() + std::size_t(r) * kFields;
    DataEstimate& p = parts[std::size_t(r)];
    p.points = std::size_t(f[0]);
    p.samples = std::size_t(f[1]);
    p.mean_radius = f[2];
    p.radius_source = RadiusSource(int(f[3]));
    p.area_spacing = f[4];
    p.position_noise = f[5];
    p.normal_noise_deg = f[6];
    p.fit_neighbours = int(f[7]);
    p.fit_radius = f[8];
    p.feature_share = f[9];
    p.crease_length = f[10];
    p.edge_samples = std::size_t(f[11]);
    p.feature_samples = std::size_t(f[12]);
    p.curved_share = f[13];
    p.normal_error_correlation = f[14];
    p.normal_position_coupling = f[15];
    p.crease_sharpness = f[16];
    p.normal_crease_length = f[17];
    any_samples = any_samples || p.samples > 0;
    points += p.points;
  }
  if (!any_samples) {  // pool_estimates would refuse too; say it in the CLI's terms, with the cause
    const std::string message = "--auto: no rank could estimate the data (" + std::to_string(ranks) + " ranks, " +
                                std::to_string(points) + " points)";
    if (!why_not.empty()) {
      throw Error(ErrorCode::invalid_input,
                  message + "; this rank's " + std::to_string(local.size()) + " points: " + why_not);
    }
    if (points == 0) throw Error(ErrorCode::invalid_input, message);
    // A rank with points failed and throws its cause; the caller's agreement ends this rank too.
    return DataEstimate{};
  }
  return pool_estimates(parts);
}

// The one process's mean radius (the radius property's mean, or the estimate over the same
// samples), which the pooled estimate only approximates.
double one_process_mean_radius(MPI_Comm comm, const CloudView& local, RadiusSource& source) {
  const detail::GlobalFrame frame = detail::global_frame(comm, local.positions);
  std::size_t moved = 0;
  const detail::OwnedPoints owned = detail::distribute(comm, local, frame, moved);
  FilterParams params;  // units radius, mean radius not given: resolved from the points
  return detail::resolve_mean_radius(comm, local, owned, frame, params, source);
}

}  // namespace

AutoChoice detail::rule_choice(MPI_Comm comm, const Agreement& agree, const CloudView& local) {
  DataEstimate estimate;
  agree.run([&] { estimate = pooled_estimate(comm, local); });
  RadiusSource source = RadiusSource::not_used;
  double mean_radius = 0;
  agree.run([&] { mean_radius = one_process_mean_radius(comm, local, source); });
  estimate.mean_radius = mean_radius;
  estimate.radius_source = source;
  AutoChoice choice;
  agree.run([&] { choice = choose_filter_params(estimate); });
  return choice;
}

AutoChoice choose_filter_params(MPI_Comm caller_comm, const CloudView& local) {
  detail::OwnComm own_comm(caller_comm);
  const MPI_Comm comm = own_comm.get();
  const detail::Agreement agree(comm);
  return detail::rule_choice(comm, agree, local);
}

}  // namespace pnf::mpi
