// The neighbour lists of the filter in CSR form (docs/method.md, "Neighbour lists"), and the k-nearest
// table of estimate_normals: the two shapes SpatialIndex answers in.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pnf::detail {

// The neighbour lists of points [first_point, first_point + point_count) of a cloud.
// List k is indices[offsets[k] .. offsets[k + 1]); offsets[0] = 0. Indices are ids in the
// whole cloud, and every list holds its own point (distance 0).
struct CsrLists {
  std::size_t first_point = 0;
  std::size_t point_count = 0;
  std::vector<std::uint64_t> offsets;  // point_count + 1
  std::vector<std::uint32_t> indices;  // offsets.back()
};

// The k nearest other points of every point: row i is indices[i * k, (i + 1) * k), nearest
// first, never containing i itself. N rows.
struct NeighbourTable {
  std::size_t point_count = 0;
  int k = 0;
  std::vector<int> indices;  // point_count * k point ids, each in [0, point_count)

  const int* row(std::size_t point) const { return indices.data() + point * static_cast<std::size_t>(k); }
};

}  // namespace pnf::detail
