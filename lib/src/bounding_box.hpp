// The axis-aligned bounding box of a non-empty point set, for the modules that re-centre or
// quantise coordinates.
#pragma once

#include <algorithm>
#include <vector>

#include "pnf/cloud_view.hpp"

namespace pnf::detail {

struct BoundingBox {
  Vec3 low, high;
  Vec3 centre() const { return {0.5 * (low[0] + high[0]), 0.5 * (low[1] + high[1]), 0.5 * (low[2] + high[2])}; }
};

// Precondition: `positions` is not empty.
inline BoundingBox bounding_box(const Vec3ArrayView& positions) {
  BoundingBox box{positions.at(0), positions.at(0)};
  for (std::size_t i = 0; i < positions.count; ++i) {
    const Vec3 p = positions.at(i);
    for (int axis = 0; axis < 3; ++axis) {
      box.low[axis] = std::min(box.low[axis], p[axis]);
      box.high[axis] = std::max(box.high[axis], p[axis]);
    }
  }
  return box;
}

}  // namespace pnf::detail
