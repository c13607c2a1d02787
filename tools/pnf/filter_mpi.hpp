// `mpirun -np P pnf filter ...`: the filter command across the ranks of an MPI job, a thin layer
// over pnf::mpi::improve_normals (README, "Beyond one machine").
#pragma once

#include <string>

#include "pnf/filter_params.hpp"
#include "pnf/normal_filter.hpp"

namespace pnf::cli {

struct DistributedFilterRun {
  std::string in, out;
  FilterParams params;  // units, radius and --stop-change applied
  FilterOptions options;
  bool ascii = false, quiet = false, automatic = false, in_place = false;
  double stop_change = -1;  // --stop-change, < 0 when not given
};

// True when a launcher started this process as one of several: OMPI_COMM_WORLD_SIZE (mpirun),
// PMI_SIZE or SLURM_STEP_NUM_TASKS (srun) above 1 (not SLURM_NTASKS, which a batch script sees
// outside any srun too). Without one (or with one process) pnf runs as it always has, and MPI
// is not even initialised.
bool launched_as_many();

// Initialises MPI, runs the filter over MPI_COMM_WORLD, finalises; returns the exit code, the
// same on every rank. Only rank 0 prints.
int run_filter_distributed(const DistributedFilterRun& run);

}  // namespace pnf::cli
