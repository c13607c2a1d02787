// Whether an MPI launcher (mpirun, mpiexec, srun) started this process as one of several, read
// from the launcher's environment before MPI is initialised (or in builds without MPI).
#pragma once

namespace pnf::cli {

// True when OMPI_COMM_WORLD_SIZE (Open MPI's mpirun / mpiexec), PMI_SIZE (MPICH's, Intel's) or
// SLURM_STEP_NUM_TASKS (srun) is above 1 (not SLURM_NTASKS, which a batch script sees outside
// any srun too). Without one (or with one process) pnf runs as it always has, and MPI is not
// even initialised.
bool launched_as_many();

// This process's rank among them (OMPI_COMM_WORLD_RANK, PMI_RANK, SLURM_PROCID); 0 when not
// launched as one of several. Only rank 0 prints command-line errors and help.
int launched_rank();

}  // namespace pnf::cli
