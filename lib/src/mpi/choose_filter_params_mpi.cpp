// pnf::mpi::choose_filter_params: --auto across the ranks (pnf/mpi.hpp), as one process chooses.
#include <cstdint>
#include <iterator>
#include <string>
#include <vector>

#include "agreement.hpp"
#include "auto/judged_passes.hpp"
#include "auto/surface_judge.hpp"
#include "filter_engine.hpp"
#include "judged_run.hpp"
#include "own_comm.hpp"
#include "pnf/choose_filter_params.hpp"
#include "pnf/mpi.hpp"

namespace pnf::mpi {

std::vector<double> detail::gather_rows(MPI_Comm comm, const std::vector<double>& mine) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  long long count = static_cast<long long>(mine.size()), total = count;
  // Every rank checks the size, so that all refuse alike before any of them waits in the gather.
  // MPI counts are ints: past 2^31 values (about 350M points with normals) the gather would have
  // to go in pieces.
  detail::check_mpi(MPI_Allreduce(MPI_IN_PLACE, &total, 1, MPI_LONG_LONG, MPI_SUM, comm), "MPI_Allreduce");
  if (total > 2147483647LL) {
    throw Error(ErrorCode::invalid_input, "--auto across ranks gathers the cloud on rank 0 for its choice: " +
                                              std::to_string(total) + " values do not fit one MPI gather (2^31)");
  }
  std::vector<long long> counts(static_cast<std::size_t>(ranks));
  detail::check_mpi(MPI_Gather(&count, 1, MPI_LONG_LONG, counts.data(), 1, MPI_LONG_LONG, 0, comm), "MPI_Gather");
  std::vector<int> sizes(static_cast<std::size_t>(ranks)), offsets(static_cast<std::size_t>(ranks));
  for (std::size_t r = 1; r < sizes.size(); ++r) offsets[r] = offsets[r - 1] + int(counts[r - 1]);
  for (std::size_t r = 0; r < sizes.size(); ++r) sizes[r] = int(counts[r]);
  std::vector<double> all(rank == 0 ? std::size_t(total) : 0);
  detail::check_mpi(
      MPI_Gatherv(mine.data(), int(count), MPI_DOUBLE, all.data(), sizes.data(), offsets.data(), MPI_DOUBLE, 0, comm),
      "MPI_Gatherv");
  return all;
}

namespace {

std::vector<double> rows_of(const Vec3ArrayView& view) {
  std::vector<double> rows(3 * view.count);
  for (std::size_t i = 0; i < view.count; ++i) {
    const Vec3 v = view.at(i);
    for (int c = 0; c < 3; ++c) rows[3 * i + c] = v[c];
  }
  return rows;
}

// Sends rank 0's choice to every rank: each number as a double (counts stay far below 2^53),
// the rule's text after them.
void broadcast(MPI_Comm comm, AutoChoice& c) {
  DataEstimate& e = c.estimate;
  FilterParams& p = c.params;
  double f[] = {double(e.points),
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
                e.normal_crease_length,
                p.sigma_f,
                p.sigma_g,
                double(p.iterations),
                p.stop_change_deg,
                double(int(p.units)),
                p.mean_radius,
                double(c.rule.size()),
                e.normal_noise_neighbours_deg,
                e.normal_noise_chords_deg};
  detail::check_mpi(MPI_Bcast(f, int(std::size(f)), MPI_DOUBLE, 0, comm), "MPI_Bcast");
  e.points = std::size_t(f[0]);
  e.samples = std::size_t(f[1]);
  e.mean_radius = f[2];
  e.radius_source = RadiusSource(int(f[3]));
  e.area_spacing = f[4];
  e.position_noise = f[5];
  e.normal_noise_deg = f[6];
  e.fit_neighbours = int(f[7]);
  e.fit_radius = f[8];
  e.feature_share = f[9];
  e.crease_length = f[10];
  e.edge_samples = std::size_t(f[11]);
  e.feature_samples = std::size_t(f[12]);
  e.curved_share = f[13];
  e.normal_error_correlation = f[14];
  e.normal_position_coupling = f[15];
  e.crease_sharpness = f[16];
  e.normal_crease_length = f[17];
  p.sigma_f = f[18];
  p.sigma_g = f[19];
  p.iterations = int(f[20]);
  p.stop_change_deg = f[21];
  p.units = Units(int(f[22]));
  p.mean_radius = f[23];
  c.rule.resize(std::size_t(f[24]));
  e.normal_noise_neighbours_deg = f[25];
  e.normal_noise_chords_deg = f[26];
  detail::check_mpi(MPI_Bcast(c.rule.data(), int(c.rule.size()), MPI_CHAR, 0, comm), "MPI_Bcast");
}

}  // namespace

AutoChoice detail::rule_choice(MPI_Comm comm, const Agreement& agree, const CloudView& local, RootJudge* root) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  // The whole cloud on rank 0, as one process would read it: the estimate (and the judge) there
  // are one process's, whatever the ranks and their slices.
  std::vector<double> positions, normals, radii;
  agree.run([&] {
    positions = detail::gather_rows(comm, rows_of(local.positions));
    normals = detail::gather_rows(comm, rows_of(local.normals));
    std::vector<double> my_radii;
    if (local.has_radii()) {
      for (std::size_t i = 0; i < local.size(); ++i) my_radii.push_back(local.radii.get(i));
    }
    radii = detail::gather_rows(comm, my_radii);
  });
  AutoChoice choice;
  agree.run([&] {
    if (rank != 0) return;
    const std::size_t n = positions.size() / 3;
    if (root && normals.empty() && n > 0) {
      throw Error(ErrorCode::invalid_input,
                  "improve_normals_auto: the cloud has no normals; estimate them first (pnf estimate, or "
                  "pnf::estimate_normals)");
    }
    if (!normals.empty() && normals.size() != positions.size()) {
      throw Error(ErrorCode::invalid_input, "--auto: some ranks' points have normals and others' do not");
    }
    if (!radii.empty() && radii.size() != n) {
      throw Error(ErrorCode::invalid_input, "--auto: some ranks' points have radii and others' do not");
    }
    const CloudView whole(Vec3ArrayView(positions.data(), n),
                          normals.empty() ? Vec3ArrayView() : Vec3ArrayView(normals.data(), n),
                          radii.empty() ? ScalarArrayView() : ScalarArrayView(radii));
    pnf::detail::SurfaceJudge judge;
    choice = choose_filter_params(pnf::detail::estimate_data(whole, root ? &judge : nullptr));
    if (root) {
      root->judge = std::move(judge);
      root->input_normals = pnf::detail::unit_rows(whole.normals);
      pnf::detail::prepare_judge(root->judge, choice, root->input_normals.data());
      if (pnf::detail::tries_held_out(choice, root->judge.plane_fits())) {
        root->held_out = pnf::detail::HeldOutPlanes(whole.positions, root->input_normals);
      }
      if (pnf::detail::stein_decides(choice)) {
        root->stein = pnf::detail::SteinRisk(pnf::detail::stein_samples(whole.positions), root->input_normals,
                                             pnf::detail::stein_noise_deg(choice));
      }
    }
  });
  broadcast(comm, choice);
  if (root) {
    long long known[5] = {1, 0, 0, 0, 0};
    if (rank == 0) {
      known[0] = root->judge.empty() ? 1 : 0;
      known[1] = root->judge.plane_fits();
      known[2] = root->judge.scored();
      known[3] = static_cast<long long>(root->input_normals.size() / 3);
      known[4] = static_cast<long long>(root->judge.size());
    }
    detail::check_mpi(MPI_Bcast(known, 5, MPI_LONG_LONG, 0, comm), "MPI_Bcast");
    root->empty = known[0] != 0;
    root->plane_fits = int(known[1]);
    root->fit_points = int(known[2]);
    root->cloud_points = std::size_t(known[3]);
    root->samples = std::size_t(known[4]);
    // What judge_error_deg and judge_cannot_see_gains weigh before any pass, where they may apply.
    if (!root->empty && pnf::detail::noise_bounding_judge_deg(choice, root->plane_fits) >= 0) {
      double input[2] = {0, 0};
      if (rank == 0) {
        root->judge.keep_input_sums(root->input_normals.data());  // kept for the judged runs
        const pnf::detail::SurfaceJudge::Sums sums = root->judge.input_sums(root->input_normals.data());
        input[0] = sums.rms_deg();
        input[1] = sums.own_error_deg();
      }
      detail::check_mpi(MPI_Bcast(input, 2, MPI_DOUBLE, 0, comm), "MPI_Bcast");
      root->input_rms_deg = input[0];
      root->own_error_deg = input[1];
    }
  }
  return choice;
}

AutoChoice choose_filter_params(MPI_Comm caller_comm, const CloudView& local) {
  detail::OwnComm own_comm(caller_comm);
  const MPI_Comm comm = own_comm.get();
  const detail::Agreement agree(comm);
  return detail::rule_choice(comm, agree, local, nullptr);
}

}  // namespace pnf::mpi
