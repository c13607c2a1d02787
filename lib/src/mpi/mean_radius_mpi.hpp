// The mean surfel radius of a distributed run, as one process resolves it (FilterParams::
// mean_radius): given, the mean of every rank's radii, or estimate_mean_radius's median.
#pragma once

#include <mpi.h>

#include "partition.hpp"
#include "pnf/filter_params.hpp"
#include "pnf/normal_filter.hpp"

namespace pnf::mpi::detail {

// Collective. 0 with Units::absolute. The estimate is bit-identical to one process's: the same
// samples (every (N / S)-th point along the one process's curve, S = min(N, 100,000), known here
// from each owned point's global curve rank), each sample's 4 nearest found exactly over its
// owner's points and a halo as wide as the largest 4th-nearest distance among the owner's points
// alone (an upper bound of the true one), distances measured on positions re-centred on
// `origin` (sample_median's) as one process does, and the median taken on rank 0 over all
// samples. Throws pnf::Error(invalid_input) as one process does when it cannot be estimated, and
// when some ranks' points have radii and others' do not.
double resolve_mean_radius(MPI_Comm comm, const CloudView& local, const OwnedPoints& owned, const GlobalFrame& frame,
                           const Vec3& origin, const FilterParams& params, RadiusSource& source);

// Collective. One process's origin (pnf::detail::sample_median: per axis, the median of the
// spacing samples), bit for bit: each rank's share of the samples, gathered on every rank. At
// least one point over all ranks.
Vec3 sample_median(MPI_Comm comm, const OwnedPoints& owned);

}  // namespace pnf::mpi::detail
