// Orders points along a space-filling curve so that neighbours sit near each other in memory.
#pragma once

#include <cstdint>
#include <vector>

#include "pnf/cloud_view.hpp"

namespace pnf::detail {

// A permutation of 0..N-1: order[k] is the input index of the k-th point along the Morton
// (Z-order) curve of the bounding box (pnf::bounding_box), 21 bits per axis; ties keep input
// order. Deterministic. positions: N by 3, any view.
std::vector<std::uint32_t> morton_order(const Vec3ArrayView& positions);

}  // namespace pnf::detail
