// --auto's cross-validation across the ranks of a distributed run: the one process's
// cross_validate (lib/src/auto/cross_validate.hpp) on the concatenation of every rank's points.
#pragma once

#include <mpi.h>

#include "agreement.hpp"
#include "auto/cross_validate.hpp"
#include "pnf/cloud_view.hpp"
#include "pnf/normal_filter.hpp"

namespace pnf::mpi::detail {

// Collective. The same held-out points as one process (rank 0 draws them as one process does,
// over the points' indices in rank order, and sends the ids), the same settings, the same
// neighbours for each held-out point: each rank holds out its owned points of the draw, runs the
// rest's passes as a distributed run does (a halo of the rest within the widest reach of every
// owned point, exchanged after every pass) and follows its own held-out points; the scores are
// summed over the ranks. So the choice is one process's, up to the order of floating-point sums.
// Every collective step is preceded by `agree`'s check, so one rank's failure (or rank 0's
// progress cancelling) ends it on every rank: all throw AgreedError with the failing rank's
// message. `progress` is called on rank 0 only.
pnf::detail::CrossValidation cross_validate(MPI_Comm comm, const Agreement& agree, const CloudView& local,
                                            double mean_radius, double position_noise, const FilterOptions& options,
                                            const ProgressCallback& progress);

}  // namespace pnf::mpi::detail
