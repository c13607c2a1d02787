// Internal: the sign-fixing steps of estimate_normals (see pnf/estimate_normals.hpp).
#pragma once

#include <cstddef>
#include <vector>

#include "pnf/point_cloud.hpp"
#include "spatial/csr_lists.hpp"

namespace pnf::detail {

// Flips normals[i] where normals[i] · (viewpoint − positions[i]) < 0. Shapes: N and N.
void orient_towards_viewpoint(const std::vector<Vec3>& positions, const Vec3& viewpoint, std::vector<Vec3>& normals);

// Flips normals[i] where normals[i] · (positions[i] − c) < 0, c the mean of positions.
void orient_outward(const std::vector<Vec3>& positions, std::vector<Vec3>& normals);

// Hoppe et al. 1992 propagation over the minimum spanning forest of the symmetric graph given by
// `neighbours` (an edge i–j when j is in row i or i in row j), edge weight 1 − |n_i · n_j|. Each
// connected component is seeded at its largest-z point (ties: smallest id), flipped to
// n_z >= 0; every other point is flipped to agree with its tree parent. Kruskal's algorithm
// (parallel sort, union-find) then a breadth-first traversal: O(N k log(N k)) time, about
// 20 N k bytes. Deterministic for any thread count.
// Preconditions: normals are unit length; neighbours.point_count == positions.size().
void orient_by_mst(const std::vector<Vec3>& positions, const NeighbourTable& neighbours, std::vector<Vec3>& normals);

}  // namespace pnf::detail
