// Small conversions between the binding's inputs and the library's value types.
#pragma once

#include <vector>

#include "pnf/cloud_view.hpp"
#include "pnf/point_cloud.hpp"

namespace pnf::python {

// The rows of a view as a vector (a copy): for the entry points that take std::vector<Vec3>.
inline std::vector<Vec3> to_vectors(const Vec3ArrayView& view) {
  std::vector<Vec3> values(view.count);
  for (std::size_t i = 0; i < view.count; ++i) values[i] = view.at(i);
  return values;
}

inline std::vector<double> to_scalars(const ScalarArrayView& view) {
  std::vector<double> values(view.count);
  for (std::size_t i = 0; i < view.count; ++i) values[i] = view.get(i);
  return values;
}

// A PointCloud holding a copy of the view, for the entry points that take a PointCloud.
inline PointCloud to_point_cloud(const CloudView& view) {
  PointCloud cloud;
  cloud.positions = to_vectors(view.positions);
  cloud.normals = to_vectors(view.normals);
  cloud.radii = to_scalars(view.radii);
  return cloud;
}

}  // namespace pnf::python
