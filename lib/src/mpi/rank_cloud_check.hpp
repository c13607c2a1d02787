// The one check of the points a rank passes to a distributed run.
#pragma once

#include <mpi.h>

#include "pnf/cloud_view.hpp"

namespace pnf::mpi::detail {

// Collective (one MPI_Exscan, first, on every rank). The filter's check of this rank's points
// (pnf::detail::check_cloud): throws its pnf::Error, the message saying where this rank's
// vertex 0 falls among all ranks' points in rank order.
void check_rank_cloud(MPI_Comm comm, const CloudView& local);

}  // namespace pnf::mpi::detail
