#include "filter_mpi.hpp"

#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "agreement.hpp"
#include "cli_common.hpp"
#include "commands.hpp"
#include "ply_slices.hpp"
#include "pnf/auto_params.hpp"
#include "pnf/mpi.hpp"
#include "pnf/point_file.hpp"

namespace pnf::cli {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
using mpi::detail::AgreedError;

// Rank 0's whole file, split evenly over the ranks in input order (ascii PLY, text formats).
PointCloud scatter_cloud(MPI_Comm comm, const PointCloud& whole, int rank, int ranks) {
  unsigned long long header[2] = {whole.size(), whole.radii.empty() ? 0ull : 1ull};
  MPI_Bcast(header, 2, MPI_UNSIGNED_LONG_LONG, 0, comm);
  std::vector<int> counts(static_cast<std::size_t>(ranks)), displs(static_cast<std::size_t>(ranks));
  for (int r = 0; r < ranks; ++r) {
    displs[std::size_t(r)] = int(header[0] * std::size_t(r) / std::size_t(ranks));
    counts[std::size_t(r)] = int(header[0] * std::size_t(r + 1) / std::size_t(ranks)) - displs[std::size_t(r)];
  }
  PointCloud part;
  const std::size_t n = std::size_t(counts[std::size_t(rank)]);
  part.positions.resize(n);
  part.normals.resize(n);
  if (header[1]) part.radii.resize(n);
  std::vector<int> counts3 = counts, displs3 = displs;
  for (int r = 0; r < ranks; ++r) counts3[std::size_t(r)] *= 3, displs3[std::size_t(r)] *= 3;
  MPI_Scatterv(rank == 0 ? whole.positions.data() : nullptr, counts3.data(), displs3.data(), MPI_DOUBLE,
               part.positions.data(), int(3 * n), MPI_DOUBLE, 0, comm);
  MPI_Scatterv(rank == 0 ? whole.normals.data() : nullptr, counts3.data(), displs3.data(), MPI_DOUBLE,
               part.normals.data(), int(3 * n), MPI_DOUBLE, 0, comm);
  if (header[1]) {
    MPI_Scatterv(rank == 0 ? whole.radii.data() : nullptr, counts.data(), displs.data(), MPI_DOUBLE, part.radii.data(),
                 int(n), MPI_DOUBLE, 0, comm);
  }
  return part;
}

std::vector<Vec3> gather_normals(MPI_Comm comm, const std::vector<Vec3>& mine, std::size_t total, int rank, int ranks) {
  int count = int(3 * mine.size());
  std::vector<int> counts(static_cast<std::size_t>(ranks)), displs(static_cast<std::size_t>(ranks), 0);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
  for (int r = 1; r < ranks; ++r) displs[std::size_t(r)] = displs[std::size_t(r - 1)] + counts[std::size_t(r - 1)];
  std::vector<Vec3> all(rank == 0 ? total : 0);
  MPI_Gatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, 0, comm);
  return all;
}

void print_summary(const DistributedFilterRun& run, const FilterParams& params, const mpi::DistributedSummary& s,
                   bool sliced, double read_s, double write_s) {
  const FilterSummary& l = s.local;
  std::fprintf(stderr, "pnf filter: %zu points from %s on %d ranks (read in %.2f s, %s)\n", s.points, run.in.c_str(),
               s.ranks, read_s, sliced ? "each rank its own rows" : "through rank 0");
  if (params.units == Units::radius) {
    std::fprintf(stderr, "  mean radius  %.6g (%s)\n", l.mean_radius, to_string(l.radius_source));
  }
  std::fprintf(stderr, "  sigma_f      %.6g model units, sigma_g %.6g\n", l.sigma_f, l.sigma_g);
  std::fprintf(stderr, "  ranks        %d: points per rank %zu..%zu, halo points per rank %zu..%zu\n", s.ranks,
               s.owned_min, s.owned_max, s.halo_min, s.halo_max);
  std::fprintf(stderr, "  neighbours   %zu pairs per pass over all ranks\n", s.neighbour_pairs);
  std::fprintf(stderr, "  exchange     %.3f MiB per pass in %zu messages; %.3f MiB moved once (owners, halos)\n",
               double(s.halo_bytes_per_pass) / 1048576.0, s.messages_per_pass, double(s.moved_bytes) / 1048576.0);
  std::fprintf(stderr, "  device       %s [%s] (rank 0)\n", l.device.c_str(), l.backend.c_str());
  std::fprintf(stderr, "  setup        partition %.3f s, radius %.3f s, halo %.3f s\n", s.partition_seconds,
               s.radius_seconds, s.halo_seconds);
  std::fprintf(stderr, "  passes       %zu (slowest rank):", s.pass_seconds.size());
  for (double t : s.pass_seconds) std::fprintf(stderr, " %.3f", t);
  std::fprintf(stderr, " s\n");
  std::fprintf(stderr, "  wrote        %s (%.2f s)\n", run.out.c_str(), write_s);
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

int run(const DistributedFilterRun& run, int rank, int ranks) {
  const MPI_Comm comm = MPI_COMM_WORLD;
  const mpi::detail::Agreement agree(comm);
  Stage stage = Stage::reading;
  try {
    FilterParams params = run.params;
    agree.run([&] {
      params.validate();
      run.options.validate();
      check_output_extension(run.out);
      check_not_overwriting_input(run.in, run.out, run.in_place);
    });
    auto t = Clock::now();
    mpi::detail::PlySliceLayout layout;
    agree.run([&] {
      if (lower_extension(run.in) == ".ply") layout = mpi::detail::read_slice_layout(run.in);
    });
    const bool sliced = layout.sliceable && lower_extension(run.out) == ".ply" && !run.ascii;
    mpi::detail::PlySlice slice;
    PointFile whole;  // rank 0, when not sliced
    PointCloud local;
    if (sliced) {
      agree.run([&] { slice = mpi::detail::read_slice(run.in, layout, rank, ranks); });
      local = std::move(slice.cloud);
    } else {
      PointCloud cloud;
      agree.run([&] {
        if (rank != 0) return;
        whole = read_point_file(run.in);
        if (!whole.has_normals()) {
          throw Error(
              ErrorCode::invalid_input,
              run.in + ": the vertices have no normals (nx ny nz); run `pnf estimate " + run.in + " OUT` first");
        }
        cloud = whole.cloud();
      });
      local = scatter_cloud(comm, cloud, rank, ranks);
    }
    double read_s = seconds_since(t);
    MPI_Allreduce(MPI_IN_PLACE, &read_s, 1, MPI_DOUBLE, MPI_MAX, comm);

    stage = Stage::running;
    std::vector<Vec3> normals(local.size());
    const ProgressCallback progress = rank == 0 ? progress_bar(run.quiet) : ProgressCallback{};
    mpi::DistributedSummary summary;
    if (run.automatic) {
      const auto t_auto = Clock::now();
      // Collective, agreeing on failures itself (AgreedError on every rank).
      const mpi::DistributedAutoRun judged =
          mpi::improve_normals_auto(comm, local, normals, run.options, progress, run.stop_change);
      params = judged.choice.params;
      summary = judged.summary;
      summary.local.radius_source = judged.choice.estimate.radius_source;  // handed over, not "given"
      if (rank == 0 && !run.quiet) print_auto(judged.choice, seconds_since(t_auto));
    } else {
      summary = mpi::improve_normals(comm, local, normals, params, run.options, progress);
    }

    stage = Stage::writing;
    t = Clock::now();
    if (sliced) {
      mpi::detail::write_slices(comm, run.in, run.out, layout, slice, normals);
    } else {
      const std::vector<Vec3> all = gather_normals(comm, normals, summary.points, rank, ranks);
      agree.run([&] {
        if (rank != 0) return;
        whole.set_normals(all);
        WriteOptions write;
        write.ascii = run.ascii;
        write_point_file(run.out, whole, write);
      });
    }
    if (rank == 0 && !run.quiet) print_summary(run, params, summary, sliced, read_s, seconds_since(t));
    return kOk;
  } catch (const AgreedError& e) {
    // Every rank has the same error; one prints it.
    return rank == 0 ? report(e, stage) : exit_code(e, stage);
  } catch (const Error& e) {
    // Failed inside a collective step that others may still be waiting in: end the job.
    const int code = report(
        Error(e.code(), "rank " + std::to_string(rank) + " of " + std::to_string(ranks) + ": " + e.what()), stage);
    MPI_Abort(comm, code);
    return code;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pnf: error: rank %d of %d: %s\n", rank, ranks, e.what());
    MPI_Abort(comm, kInternal);
    return kInternal;
  }
}

int environment_count(const char* name) {
  const char* value = std::getenv(name);
  return value ? std::atoi(value) : 0;
}

}  // namespace

bool launched_as_many() {
  return environment_count("OMPI_COMM_WORLD_SIZE") > 1 || environment_count("PMI_SIZE") > 1 ||
         environment_count("SLURM_STEP_NUM_TASKS") > 1;
}

int run_filter_distributed(const DistributedFilterRun& filter_run) {
  // The engine runs OpenMP threads; only this thread calls MPI.
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  const int code = run(filter_run, rank, ranks);
  MPI_Finalize();
  return code;
}

}  // namespace pnf::cli
