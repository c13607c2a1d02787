// `mpirun -np P pnf filter ...`: the filter command across the ranks of an MPI job, a thin layer
// over pnf::mpi::filter_file (README, "Beyond one machine").
#pragma once

#include <string>

#include "pnf/filter_file_options.hpp"

namespace pnf::cli {

// Initialises MPI, runs pnf::mpi::filter_file over MPI_COMM_WORLD with `options` (the value the
// one-process run takes), finalises; returns the exit code, the same on every rank. Only rank 0
// prints (progress, the summary, errors); every rank stops at SIGINT / SIGTERM as one process
// does (exit 6, OUT untouched, when the ranks get to agree on it before mpirun ends them).
int run_filter_distributed(const std::string& in, const std::string& out, const FilterFileOptions& options, bool quiet);

}  // namespace pnf::cli
