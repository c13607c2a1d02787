#include "pnf/bounding_box.hpp"

#include <algorithm>

namespace pnf {

BoundingBox BoundingBox::united(const BoundingBox& other) const {
  BoundingBox box = *this;
  for (int axis = 0; axis < 3; ++axis) {
    box.min[axis] = std::min(box.min[axis], other.min[axis]);
    box.max[axis] = std::max(box.max[axis], other.max[axis]);
  }
  return box;
}

BoundingBox bounding_box(const Vec3ArrayView& positions) {
  BoundingBox box;
  if (positions.empty()) return box;
  box.min = box.max = positions.at(0);
  for (std::size_t i = 1; i < positions.count; ++i) {
    const Vec3 p = positions.at(i);
    for (int axis = 0; axis < 3; ++axis) {
      box.min[axis] = std::min(box.min[axis], p[axis]);
      box.max[axis] = std::max(box.max[axis], p[axis]);
    }
  }
  return box;
}

}  // namespace pnf
