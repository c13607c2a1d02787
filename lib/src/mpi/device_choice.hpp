// Which device a rank of a distributed run uses.
#pragma once

#include <mpi.h>

#include "pnf/device.hpp"

namespace pnf::mpi::detail {

// Collective. `requested` resolved as NormalFilter resolves it (PNF_DEVICE); when that leaves the
// OpenCL default rule or "gpu" and this node has several GPUs, the ranks on the node
// (MPI_COMM_TYPE_SHARED) take them in turn by node-local rank ("P:D" selectors).
Device choose_device(MPI_Comm comm, const Device& requested);

}  // namespace pnf::mpi::detail
