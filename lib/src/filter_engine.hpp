// The filter's driver, independent of the backend: validation, curve ordering and re-centring,
// neighbour counting, chunk planning, passes, progress, and mapping back to input order.
#pragma once

#include "filter_backend.hpp"
#include "pnf/normal_filter.hpp"

namespace pnf::detail {

// NormalFilter::run on `backend` (see normal_filter.hpp for the contract). When the backend
// reports that the device refused an allocation (DeviceMemoryError), the run starts over with
// chunks half the size of the one refused, down to a single point's list.
FilterResult run_filter(FilterBackend& backend, const FilterOptions& options, const PointCloud& cloud,
                        const FilterParams& params, const ProgressCallback& progress);

}  // namespace pnf::detail
