// pnf::PointCloud — the points and normals the library works on.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

namespace pnf {

using Vec3 = std::array<double, 3>;

// A set of N samples. Positions are in model units; normals are oriented and expected to be
// unit length (the filter normalises them on entry); radii are optional surfel radii in model
// units. Double precision so that float32 and float64 file values both survive unchanged.
struct PointCloud {
  std::vector<Vec3> positions;  // N
  std::vector<Vec3> normals;    // N, or empty when the source had none
  std::vector<double> radii;    // N, or empty when the source had none

  std::size_t size() const { return positions.size(); }
  bool has_normals() const { return !normals.empty(); }
  bool has_radii() const { return !radii.empty(); }
};

}  // namespace pnf
