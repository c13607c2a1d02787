// The one validation of a cloud before any algorithm reads it. Each caller states what it
// needs (normals or not, a minimum size, its name for the messages); the rules for what is a
// bad value are the same everywhere.
#pragma once

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "pnf/cloud_view.hpp"

namespace pnf::detail {

struct CloudRequirements {
  // Prefixed to every message ("estimate_normals: ..."); empty for the filter.
  std::string caller;
  // Fewer points than this is an error (0: an empty cloud is fine).
  std::size_t min_points = 0;
  // Normals must be present (the filter, the renderer); otherwise they are optional and
  // checked only when present.
  bool needs_normals = false;
  // Normals, when present, are checked for NaN and zero length. The estimate of the data
  // tolerates bad input normals (it ignores them point by point).
  bool checks_normals = true;
  // Largest N allowed: point ids are 32-bit on the device (2^32 - 2) and int in the estimate.
  std::size_t max_points = std::size_t(4294967294u);

  static CloudRequirements filter() { return {"", 0, true, true, std::size_t(4294967294u)}; }
};

// A surfel radius pnf can use: finite and > 0 (check_cloud's rule, and a point file's radius
// property's: filter_file_cloud.hpp).
inline bool valid_radius(double radius) { return std::isfinite(radius) && radius > 0; }

// Throws pnf::Error(invalid_input) naming the first offending vertex when: the cloud has fewer
// than min_points points or more than max_points; normals are required and absent; normals or
// radii do not match the positions in count; a coordinate or normal component is NaN or
// infinite; a normal has zero length; or a radius is not finite and > 0.
void check_cloud(const CloudView& cloud, const CloudRequirements& requirements);

// n / |n| for every normal of a checked cloud, N by 3 in view order.
std::vector<double> unit_normals(const Vec3ArrayView& normals);

}  // namespace pnf::detail
