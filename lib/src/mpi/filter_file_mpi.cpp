// pnf::mpi::filter_file: a point file filtered across the ranks (pnf/mpi.hpp): read (each rank
// its rows, or rank 0 and a scatter), filter, the whole job's pair count, write (each rank its
// rows, or a gather and rank 0) into a staging folder, commit.
#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "agreement.hpp"
#include "filter_file_cloud.hpp"
#include "own_comm.hpp"
#include "ply_slices.hpp"
#include "pnf/mpi.hpp"
#include "pnf/point_file.hpp"
#include "staged_output.hpp"

namespace pnf::mpi {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// What the one-process `pnf filter` refuses before it reads anything.
void check_paths(const std::string& in, const std::string& out, bool in_place, const WriteOptions& write) {
  point_file_format(out);
  check_write_options(out, write);
  std::error_code ec;
  if (!in_place && std::filesystem::equivalent(in, out, ec)) {
    throw Error(ErrorCode::invalid_argument, out + " is the input file; pass --in-place to overwrite it");
  }
}

// Rank 0's whole cloud, split evenly over the ranks in input order.
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

// Every rank's normals, in rank order, on rank 0.
std::vector<Vec3> gather_normals(MPI_Comm comm, const std::vector<Vec3>& mine, std::size_t total, int rank, int ranks) {
  int count = int(3 * mine.size());
  std::vector<int> counts(static_cast<std::size_t>(ranks)), displs(static_cast<std::size_t>(ranks), 0);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
  for (int r = 1; r < ranks; ++r) displs[std::size_t(r)] = displs[std::size_t(r - 1)] + counts[std::size_t(r - 1)];
  std::vector<Vec3> all(rank == 0 ? total : 0);
  MPI_Gatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, 0, comm);
  return all;
}

double max_over(MPI_Comm comm, double value) {
  MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_DOUBLE, MPI_MAX, comm);
  return value;
}

}  // namespace

FileRun filter_file(MPI_Comm caller_comm, const std::string& in_path, const std::string& out_path,
                    const FilterFileOptions& options, const ProgressCallback& progress, FileStep* step) {
  FileStep ignored = FileStep::reading;
  FileStep& at = step ? *step : ignored;
  at = FileStep::reading;
  const detail::OwnComm own_comm(caller_comm);
  const MPI_Comm comm = own_comm.get();
  const detail::Agreement agree(comm);
  const int rank = agree.rank(), ranks = agree.size();
  FileRun run;
  run.params = options.run_params();
  agree.run([&] {
    if (!options.automatic) run.params.validate();
    options.options.validate();
    check_paths(in_path, out_path, options.in_place, options.write);
  });

  auto t = Clock::now();
  detail::PlySliceLayout layout;
  agree.run([&] {
    if (point_file_format(in_path) == PointFileFormat::ply) layout = detail::read_slice_layout(in_path);
  });
  run.sliced = layout.sliceable && point_file_format(out_path) == PointFileFormat::ply && !options.write.ascii;
  detail::PlySlice slice;
  PointFile whole;  // rank 0, when not sliced
  PointCloud local;
  if (run.sliced) {
    agree.run([&] { slice = detail::read_slice(in_path, layout, rank, ranks); });
    local = std::move(slice.cloud);
    // As cloud_to_filter does for the one process (no invalid rows here: a sliced file has none).
    if (!reads_radii(options)) local.radii.clear();
    agree.run(
        [&] { pnf::detail::check_file_radii(local.radii, in_path, [&](std::size_t i) { return slice.first + i; }); });
  } else {
    PointCloud cloud;
    agree.run([&] {
      if (rank != 0) return;
      whole = read_point_file(in_path);
      if (!whole.has_normals()) {
        throw Error(
            ErrorCode::invalid_input,
            in_path + ": the vertices have no normals (nx ny nz); run `pnf estimate " + in_path + " OUT` first");
      }
      cloud = cloud_to_filter(whole, in_path, options);
      run.kept_without_normals = whole.without_normals();
      run.invalid_rows = whole.size() - whole.valid_count() - whole.without_normals();
    });
    local = scatter_cloud(comm, cloud, rank, ranks);
  }
  run.read_seconds = max_over(comm, seconds_since(t));

  at = FileStep::filtering;
  std::vector<Vec3> normals(local.size());
  if (options.automatic) {
    t = Clock::now();
    const DistributedAutoRun judged =
        improve_normals_auto(comm, local, normals, options.options, progress, options.stop_change_deg);
    run.choice = judged.choice;
    run.params = judged.choice.params;
    run.summary = judged.summary;
    run.summary.local.radius_source = judged.choice.estimate.radius_source;  // handed over, not "given"
    run.auto_seconds = max_over(comm, seconds_since(t));
  } else {
    run.summary = improve_normals(comm, local, normals, run.params, options.options, progress);
  }
  // Each rank's engine refused its own estimate above the limit; the job's count is all ranks'.
  // The same sum on every rank: every rank throws alike.
  const std::size_t limit = options.options.memory.max_neighbour_pairs;
  if (run.summary.neighbour_pairs > limit) {
    throw detail::AgreedError(
        ErrorCode::invalid_argument,
        "the neighbour lists of all " + std::to_string(ranks) + " ranks hold " +
            std::to_string(run.summary.neighbour_pairs) + " pairs, more than the limit of " + std::to_string(limit) +
            " pairs for the whole job; lower sigma_f, or raise MemoryPolicy::max_neighbour_pairs (pnf filter "
            "--max-pairs). Nothing was written");
  }

  at = FileStep::writing;
  t = Clock::now();
  detail::StagedOutput staged(agree, comm, out_path);
  if (run.sliced) {
    detail::write_slices(comm, in_path, staged.path(), layout, slice, normals);
  } else {
    const std::vector<Vec3> all = gather_normals(comm, normals, run.summary.points, rank, ranks);
    agree.run([&] {
      if (rank != 0) return;
      whole.set_normals(all);
      write_point_file(staged.path(), whole, options.write);
    });
  }
  const int passes = int(run.summary.pass_seconds.size());
  staged.commit(progress, passes, passes);
  run.write_seconds = max_over(comm, seconds_since(t));
  return run;
}

}  // namespace pnf::mpi
