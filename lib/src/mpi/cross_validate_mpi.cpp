// Distributed cross-validation (cross_validate_mpi.hpp).
#include "cross_validate_mpi.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "device_choice.hpp"
#include "filter_engine.hpp"
#include "halo.hpp"
#include "partition.hpp"
#include "rank_cloud_check.hpp"

namespace pnf::mpi::detail {
namespace {

using pnf::detail::FoldRows;
using pnf::detail::HeldOutDraw;

// Rank 0's draw over all the points, sent to every rank.
HeldOutDraw shared_draw(MPI_Comm comm, std::size_t total) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  HeldOutDraw draw;
  if (rank == 0) draw = pnf::detail::draw_held_out(total);
  unsigned long long sizes[2] = {draw.held, draw.folds};
  check_mpi(MPI_Bcast(sizes, 2, MPI_UNSIGNED_LONG_LONG, 0, comm), "MPI_Bcast");
  draw.held = std::size_t(sizes[0]);
  draw.folds = std::size_t(sizes[1]);
  // At most 50000 ids, or half of a cloud under 80000 points.
  draw.ids.resize(draw.held * draw.folds);
  check_mpi(MPI_Bcast(draw.ids.data(), int(draw.ids.size()), MPI_UINT32_T, 0, comm), "MPI_Bcast");
  return draw;
}

// For each owned point, its place in the draw (draw.ids.size() when not drawn).
std::vector<std::size_t> places_in_draw(const OwnedPoints& owned, const HeldOutDraw& draw) {
  std::vector<std::pair<std::uint64_t, std::size_t>> by_id(draw.ids.size());
  for (std::size_t j = 0; j < draw.ids.size(); ++j) by_id[j] = {draw.ids[j], j};
  std::sort(by_id.begin(), by_id.end());
  std::vector<std::size_t> place(owned.size(), draw.ids.size());
  for (std::size_t i = 0; i < owned.size(); ++i) {
    const auto at = std::lower_bound(by_id.begin(), by_id.end(), std::make_pair(owned.gids[i], std::size_t(0)));
    if (at != by_id.end() && at->first == owned.gids[i]) place[i] = at->second;
  }
  return place;
}

Vec3 row(const std::vector<double>& values, std::size_t i) {
  return {values[3 * i], values[3 * i + 1], values[3 * i + 2]};
}

// One fold as this rank holds it: its owned points drawn into [first, last) held out, in the
// draw's order (so that those one process nudges, the fold's first, come first here too); the
// others, then their halo: other ranks' rest within `reach` of any owned point, which covers both
// this rank's rest (its passes) and its held-out points (their neighbours). `plan` gets the
// halo's exchange.
FoldRows fold_rows(MPI_Comm comm, const OwnedPoints& owned, const std::vector<std::size_t>& place, std::size_t first,
                   std::size_t last, double reach, const GlobalFrame& frame, HaloPlan& plan) {
  FoldRows rows;
  rows.centre = frame.centre();
  std::vector<std::pair<std::size_t, std::size_t>> held;  // (place, owned index)
  OwnedPoints rest;
  for (std::size_t i = 0; i < owned.size(); ++i) {
    if (place[i] >= first && place[i] < last) {
      held.emplace_back(place[i], i);
    } else {
      rest.positions.insert(rest.positions.end(), &owned.positions[3 * i], &owned.positions[3 * i] + 3);
      rest.normals.insert(rest.normals.end(), &owned.normals[3 * i], &owned.normals[3 * i] + 3);
    }
  }
  std::sort(held.begin(), held.end());
  for (const auto& [at, i] : held) {
    rows.held_positions.push_back(row(owned.positions, i));
    rows.held_normals.push_back(row(owned.normals, i));
    if (at - first < pnf::detail::nudged_per_fold()) ++rows.nudged;
  }
  const std::size_t rest_owned = rest.positions.size() / 3;
  std::vector<double> halo_positions, halo_normals;
  plan.build(comm, rest, points_near(comm, rest.positions, owned.positions, reach, frame), halo_positions,
             halo_normals);
  for (std::size_t k = 0; k < rest_owned; ++k) {
    rows.rest_positions.push_back(row(rest.positions, k));
    rows.rest_normals.push_back(row(rest.normals, k));
  }
  for (std::size_t k = 0; k < plan.halo_points(); ++k) {
    rows.rest_positions.push_back(row(halo_positions, k));
    rows.rest_normals.push_back(row(halo_normals, k));
  }
  return rows;
}

pnf::detail::CrossValidation agreed_cross_validate(MPI_Comm comm, const Agreement& agree, const CloudView& local,
                                                   double mean_radius, double position_noise,
                                                   const FilterOptions& options, const ProgressCallback& progress) {
  unsigned long long total = local.size();
  check_mpi(MPI_Allreduce(MPI_IN_PLACE, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm), "MPI_Allreduce");
  FilterOptions resolved;
  std::unique_ptr<pnf::detail::FilterBackend> backend;
  agree.run([&] {
    if (total < pnf::detail::cross_validation_min_points()) {
      throw Error(ErrorCode::invalid_argument, "cross-validation needs " +
                                                   std::to_string(pnf::detail::cross_validation_min_points()) +
                                                   " points or more; got " + std::to_string(total));
    }
    if (!(mean_radius > 0) || !std::isfinite(mean_radius)) {
      throw Error(ErrorCode::invalid_argument, "cross-validation needs a mean radius > 0");
    }
    if (!(position_noise >= 0) || !std::isfinite(position_noise)) {
      throw Error(ErrorCode::invalid_argument,
                  "cross-validation needs a position noise >= 0 and finite, got " + std::to_string(position_noise));
    }
    // The draw numbers the points as one process does, in 32 bits (and holds a permutation of
    // them on rank 0).
    if (total > std::numeric_limits<std::uint32_t>::max() - 1) {
      throw Error(ErrorCode::invalid_argument,
                  "cross-validation takes at most 4294967294 points, as one process; got " + std::to_string(total) +
                      " (give sigma_f, sigma_g and the passes)");
    }
    check_rank_cloud(comm, local);
  });
  agree.run([&] { backend = make_rank_backend(comm, options, resolved); });  // collective: a step of its own
  const GlobalFrame frame = global_frame(comm, local.positions);
  std::size_t moved = 0;
  const OwnedPoints owned = distribute(comm, local, frame, moved);
  const HeldOutDraw draw = shared_draw(comm, std::size_t(total));
  const std::vector<std::size_t> place = places_in_draw(owned, draw);
  const double reach = pnf::detail::widest_reach_in_mean_radii() * mean_radius;

  std::vector<pnf::detail::Tally> tallies = pnf::detail::empty_tallies();
  std::vector<double> error_samples;
  std::size_t runs = 0;
  const std::size_t all_runs = draw.folds * pnf::detail::rest_runs_per_fold();
  for (std::size_t fold = 0; fold < draw.folds; ++fold) {
    agree.check();
    const std::size_t first = fold * draw.held;
    HaloPlan plan;
    FoldRows rows = fold_rows(comm, owned, place, first, first + draw.held, reach, frame, plan);
    rows.position_noise = position_noise;
    const std::size_t rest_owned = rows.rest_positions.size() - plan.halo_points();
    const CloudView view(rows.rest_positions, rows.rest_normals);
    std::vector<Vec3> rest_out(rest_owned);
    const pnf::detail::RestPassObserver* after_pass = nullptr;
    int pass = 0;
    std::vector<double> rest_normals;
    pnf::detail::DistributedPart part;
    part.owned = rest_owned;
    part.exchange_halo = [&](const std::vector<double>& own, std::vector<double>& halo) {
      agree.check();  // a rank that failed in its pass or its held-out points ends it here
      plan.exchange(own, halo);
      rest_normals = own;
      rest_normals.insert(rest_normals.end(), halo.begin(), halo.end());
      (*after_pass)(++pass, rest_normals);
    };
    part.sum_over_processes = [&](double* values, int count) {
      check_mpi(MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_DOUBLE, MPI_SUM, comm), "MPI_Allreduce");
    };
    auto run_rest = [&](const FilterParams& params, const pnf::detail::RestPassObserver& observer,
                        const ProgressCallback& still_wanted) {
      after_pass = &observer;
      pass = 0;
      pnf::detail::run_filter(*backend, resolved, view, MutableVec3ArrayView(rest_out), params, still_wanted, &part);
    };
    pnf::detail::score_fold(rows, mean_radius, run_rest, progress, tallies, error_samples, runs, all_runs);
  }
  agree.check();
  static_assert(sizeof(pnf::detail::Tally) == 4 * sizeof(double), "a Tally is summed as 4 doubles");
  check_mpi(MPI_Allreduce(MPI_IN_PLACE, tallies.data(), int(4 * tallies.size()), MPI_DOUBLE, MPI_SUM, comm),
            "MPI_Allreduce");
  // Every rank's error samples, for the one process's variance over all of them.
  int mine = int(error_samples.size()), ranks = 1;
  MPI_Comm_size(comm, &ranks);
  std::vector<int> counts(std::size_t(ranks), 0);
  check_mpi(MPI_Allgather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, comm), "MPI_Allgather");
  const std::vector<int> offsets = displacements(counts);
  std::vector<double> all_samples(std::size_t(offsets.back()) + std::size_t(counts.back()));
  check_mpi(MPI_Allgatherv(error_samples.data(), mine, MPI_DOUBLE, all_samples.data(), counts.data(), offsets.data(),
                           MPI_DOUBLE, comm),
            "MPI_Allgatherv");
  return pnf::detail::best_setting(tallies, draw, mean_radius, pnf::detail::input_error_variance(all_samples));
}

}  // namespace

pnf::detail::CrossValidation cross_validate(MPI_Comm comm, const Agreement& agree, const CloudView& local,
                                            double mean_radius, double position_noise, const FilterOptions& options,
                                            const ProgressCallback& progress) {
  // A rank that fails between the agreed steps (in its held-out passes, or rank 0 cancelling)
  // meets the others' next check here.
  pnf::detail::CrossValidation cv;
  agree.run([&] { cv = agreed_cross_validate(comm, agree, local, mean_radius, position_noise, options, progress); });
  return cv;
}

}  // namespace pnf::mpi::detail
