#include "filter_mpi.hpp"

#include <mpi.h>

#include <cstdio>
#include <string>

#include "cli_common.hpp"
#include "pnf/mpi.hpp"

namespace pnf::cli {
namespace {

void print_summary(const std::string& in, const std::string& out, const mpi::FileRun& run, bool automatic) {
  const mpi::DistributedSummary& s = run.summary;
  const FilterSummary& l = s.local;
  std::fprintf(stderr, "pnf filter: %zu points from %s on %d ranks (read in %.2f s, %s)\n", s.points, in.c_str(),
               s.ranks, run.read_seconds, run.sliced ? "each rank its own rows" : "through rank 0");
  if (run.params.units == Units::radius) {
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
  if (s.pass_seconds.empty()) {
    std::fprintf(stderr, "  passes       none\n");
  } else {
    std::fprintf(stderr, "  passes       %zu (slowest rank):", s.pass_seconds.size());
    for (double t : s.pass_seconds) std::fprintf(stderr, " %.3f", t);
    std::fprintf(stderr, " s\n");
  }
  if (!automatic && run.params.stop_change_deg > 0 && !l.mean_change_deg.empty()) {
    std::fprintf(stderr, "  stop rule    %zu of at most %d passes run (below %g deg); mean change per pass:",
                 s.pass_seconds.size(), run.params.iterations, run.params.stop_change_deg);
    for (double d : l.mean_change_deg) std::fprintf(stderr, " %.3g", d);
    std::fprintf(stderr, " deg\n");
  }
  std::fprintf(stderr, "  wrote        %s (%.2f s)\n", out.c_str(), run.write_seconds);
  print_rows_not_filtered(run.kept_without_normals, run.invalid_rows, out);
}

Stage stage_of(mpi::FileStep step) {
  switch (step) {
    case mpi::FileStep::reading: return Stage::reading;
    case mpi::FileStep::filtering: return Stage::running;
    case mpi::FileStep::writing: return Stage::writing;
  }
  return Stage::running;
}

int run(const std::string& in, const std::string& out, const FilterFileOptions& options, bool quiet, int rank,
        int ranks) {
  mpi::FileStep step = mpi::FileStep::reading;
  try {
    // Every rank stops at SIGINT / SIGTERM (mpirun passes them on); rank 0 alone draws.
    const ProgressCallback progress = progress_bar(quiet || rank != 0);
    const mpi::FileRun done = mpi::filter_file(MPI_COMM_WORLD, in, out, options, progress, &step);
    if (rank == 0 && !quiet) {
      if (options.automatic) print_auto(done.choice, done.auto_seconds);
      print_summary(in, out, done, options.automatic);
    }
    return kOk;
  } catch (const mpi::AgreedError& e) {
    // Every rank has the same error; one prints it.
    return rank == 0 ? report(e, stage_of(step)) : exit_code(e, stage_of(step));
  } catch (const Error& e) {
    // Failed inside a collective step that others may still be waiting in: end the job.
    const int code =
        report(Error(e.code(), "rank " + std::to_string(rank) + " of " + std::to_string(ranks) + ": " + e.what()),
               stage_of(step));
    MPI_Abort(MPI_COMM_WORLD, code);
    return code;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pnf: error: rank %d of %d: %s\n", rank, ranks, e.what());
    MPI_Abort(MPI_COMM_WORLD, kInternal);
    return kInternal;
  }
}

}  // namespace

int run_filter_distributed(const std::string& in, const std::string& out, const FilterFileOptions& options,
                           bool quiet) {
  // The engine runs OpenMP threads; only this thread calls MPI.
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  const int code = run(in, out, options, quiet, rank, ranks);
  MPI_Finalize();
  return code;
}

}  // namespace pnf::cli
