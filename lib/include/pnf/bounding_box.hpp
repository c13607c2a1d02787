// pnf::BoundingBox, pnf::bounding_box — the axis-aligned box of a point set, the one box type of
// pnf (the renderer's frame, compare's shared camera, the re-centring of the filter, estimate and
// --auto, the Morton order's grid).
#pragma once

#include "pnf/cloud_view.hpp"
#include "pnf/point_cloud.hpp"

namespace pnf {

// An axis-aligned box in model units; min <= max on each axis for a box of points.
struct BoundingBox {
  Vec3 min{0, 0, 0};
  Vec3 max{0, 0, 0};

  // (min + max) / 2, per axis: the point pnf re-centres a cloud on before anything becomes float.
  Vec3 centre() const { return {0.5 * (min[0] + max[0]), 0.5 * (min[1] + max[1]), 0.5 * (min[2] + max[2])}; }
  // max - min, per axis.
  Vec3 extent() const { return {max[0] - min[0], max[1] - min[1], max[2] - min[2]}; }
  // The smallest box holding this one and `other`.
  BoundingBox united(const BoundingBox& other) const;
};

// The smallest box holding every one of the N positions (N by 3, any view); the all-zero box
// when N = 0. Coordinates are compared as read (NaN is not checked for here: validate first).
// Cost O(N). Thread safety: pure function.
BoundingBox bounding_box(const Vec3ArrayView& positions);

}  // namespace pnf
