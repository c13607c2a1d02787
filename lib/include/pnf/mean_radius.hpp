// pnf::estimate_mean_radius — the surfel radius used when a cloud carries none.
#pragma once

#include <vector>

#include "pnf/point_cloud.hpp"

namespace pnf {

// Estimates the mean surfel radius (the sample spacing) of N points, in model units: the
// median, over up to 100,000 points spread evenly through the cloud, of each point's mean
// distance to its 4 nearest other points. On a square grid of spacing h this is exactly h (the
// 4 nearest are the edge neighbours); on a jittered grid it stays within a few percent of h.
// Points whose 4 nearest are all duplicates of themselves are left out, and the median ignores
// outliers. Returns 0 when N < 5 or when every point sits on top of 4 others. Thread safety: may be called
// concurrently.
double estimate_mean_radius(const std::vector<Vec3>& positions);

}  // namespace pnf
