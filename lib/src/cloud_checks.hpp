// Validation of a PointCloud before it reaches a filter backend.
#pragma once

#include <vector>

#include "pnf/point_cloud.hpp"

namespace pnf::detail {

// Throws pnf::Error(invalid_input) naming the first offending vertex when: the cloud has no
// normals, normals or radii do not match the positions in count, a coordinate or normal
// component is NaN or infinite, a normal has zero length, or a radius is not finite and > 0;
// or when the cloud has 2^32 - 1 points or more (point ids are 32-bit on the device).
void check_cloud(const PointCloud& cloud);

// n / |n| for every normal of a checked cloud.
std::vector<Vec3> unit_normals(const std::vector<Vec3>& normals);

}  // namespace pnf::detail
