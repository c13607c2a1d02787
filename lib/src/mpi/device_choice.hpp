// Which device a rank of a distributed run uses.
#pragma once

#include <mpi.h>

#include <memory>

#include "filter_backend.hpp"
#include "pnf/device.hpp"
#include "pnf/normal_filter.hpp"

namespace pnf::mpi::detail {

// Collective. `requested` resolved as NormalFilter resolves it (PNF_DEVICE); when that leaves the
// OpenCL default rule or "gpu" and this node has several GPUs, the ranks on the node
// (MPI_COMM_TYPE_SHARED) take them in turn by node-local rank ("P:D" selectors).
Device choose_device(MPI_Comm comm, const Device& requested);

// Collective: this rank's backend for `options` (its device by choose_device); `resolved` gets
// the options with that device.
std::unique_ptr<pnf::detail::FilterBackend> make_rank_backend(MPI_Comm comm, const FilterOptions& options,
                                                              FilterOptions& resolved);

}  // namespace pnf::mpi::detail
