// The refusals that come before a run's neighbour lists are built: a neighbourhood so wide that
// the lists would pass MemoryPolicy::max_neighbour_pairs, and work that would run longer than
// FilterOptions::max_seconds on this device.
#pragma once

#include <string>

#include "filter_backend.hpp"
#include "filter_engine.hpp"

namespace pnf::detail {

// Estimates the neighbour pairs of the whole view from a sample (cheap where the exact count
// would take hours) and returns it; throws pnf::Error(invalid_argument) when it passes
// options.memory.max_neighbour_pairs. With a distributed part's job_sum, the limit is the whole
// job's: the owned points' shares of every process, added (each throws alike).
double check_pair_limit(const PreparedCloud& prepared, const FilterOptions& options,
                        const DistributedPart* part = nullptr);

// The same for a distributed part with no points: it adds nothing, but takes part in the job's
// sum and refuses with the others.
void check_idle_pair_limit(const DistributedPart& part, const FilterOptions& options);

// With options.max_seconds > 0 and work large enough to matter, times `backend` on a compact
// piece of the cloud (it uploads the cloud and builds a probe's lists: the caller uploads again)
// and throws pnf::Error(invalid_argument), naming `device`, when the owned points' lists and
// `passes` passes would take longer than the limit. pair_estimate: check_pair_limit's.
void check_time_limit(FilterBackend& backend, const PreparedCloud& prepared, const FilterOptions& options,
                      double pair_estimate, int passes, const std::string& device);

}  // namespace pnf::detail
