// Orders points along a space-filling curve so that neighbours sit near each other in memory.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "pnf/cloud_view.hpp"

namespace pnf::detail {

// The order between two points of equal Morton key, or two normals of equal points: by the bits
// of x, then y, then z (as doubles). A distributed run breaks its curve's ties the same way, so
// that its points keep one process's order whatever rank holds them.
bool canonical_before(const Vec3& a, const Vec3& b);

// The curve's frame: its lowest corner and cells per model unit. A distributed run (pnf/mpi.hpp)
// builds it from the global box and sample so that every rank computes the keys one process would.
struct MortonFrame {
  Vec3 low = {0, 0, 0};
  double to_cells = 0;
};
// The frame of points whose bounding box is [low, high]: that box, unless it is more than
// kFarBoxPerBulk times as wide as the box of the points' bulk (per axis, the sample's coordinates
// from its 0.1% to its 99.9% quantile, widened by an eighth on each side), as one far point makes
// it (a sensor's stray return, a (0, 0, 0) row among georeferenced points): then the bulk's, and
// the points beyond it take the cells on its faces. In the box of a point 1e9 away the curve put
// a unit cloud's points into one cell, ordered along x only, and the filter's runs took twice
// as long (docs/method.md, "Curve order"). `sample_xyz`: curve_sample's, in any order.
MortonFrame morton_frame(const Vec3& low, const Vec3& high, const std::vector<double>& sample_xyz);
// The box of all the points may be this many times the bulk's: its curve still gives the bulk
// 2^21 / 64 = 32768 cells a side, a few points a cell for a surface of 10^9 points.
constexpr double kFarBoxPerBulk = 64;
// The sample morton_frame measures the bulk on: the coordinates (by 3) of each point whose bits
// hash into one in `stride` (curve_sample_stride of the points in the whole cloud), so that a
// distributed run's ranks pick the points one process picks, whatever rank holds them (and
// every copy of a point alike).
std::uint64_t curve_sample_stride(std::uint64_t points);
// A hash of a point's coordinates (their bits, SplitMix64's finaliser after each): the same for
// every copy of the point, on every rank, whatever its row.
std::uint64_t position_hash(const Vec3& p);
std::vector<double> curve_sample(const Vec3ArrayView& positions, std::uint64_t stride);
// The `index`-th smallest (from 0) of coordinate `axis` (0-2) over the points of `xyz` (x y z per
// point, more than `index` of them): the curve frame's quantiles and the origin's medians.
double axis_order_statistic(const std::vector<double>& xyz, int axis, std::size_t index);
// morton_frame of `positions` (N by 3) as a whole cloud.
MortonFrame morton_frame_of(const Vec3ArrayView& positions);
// The Morton key of `p` in `frame` (63 bits), the key morton_order sorts by; a point beyond the
// frame takes the cell on its face.
std::uint64_t morton_key(const MortonFrame& frame, const Vec3& p);

// A permutation of 0..N-1: order[k] is the input index of the k-th point along the Morton
// (Z-order) curve of morton_frame_of(positions), 21 bits per axis. Points with the same
// key go in canonical_before's order (then, with `normals`, by the normals' bits; last, input
// order, which only identical rows still share), so that the order of the points does not depend
// on the input's row order. positions (and normals): N by 3, any view. With `frame`, the keys
// are that frame's, not the points' own box's: a distributed part orders its points as one
// process orders the whole cloud.
std::vector<std::uint32_t> morton_order(const Vec3ArrayView& positions, const Vec3ArrayView* normals = nullptr,
                                        const MortonFrame* frame = nullptr);

// rank[i]: the place of point i in `order` (a permutation such as morton_order's).
std::vector<std::uint32_t> ranks_of(const std::vector<std::uint32_t>& order);

// Puts k neighbours (ids with their squared distances, as SpatialIndex::nearest_of_point gives
// them, in the tree's order) nearest first, equal distances by rank[id] (ranks_of a curve order),
// so that sums over them round alike whatever the input's row order and the tree's layout.
void sort_neighbours(std::size_t* ids, double* squared_distances, std::size_t k,
                     const std::vector<std::uint32_t>& rank);

}  // namespace pnf::detail
