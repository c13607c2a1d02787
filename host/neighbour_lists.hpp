// Fixed-radius neighbour lists in CSR form, from a FLANN kd-tree, built on all cores.
#pragma once

#include <cstdint>
#include <memory>
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

// A kd-tree over N points, searched in parallel with OpenMP. All distances here are plain
// Euclidean distances in model units; FLANN's squared distances stay inside the .cpp.
// Thread safety: const methods may run concurrently.
class NeighbourSearch {
 public:
  // positions: N by 3, row-major, in model units. Copied into the tree.
  NeighbourSearch(const double* positions, std::size_t point_count);
  ~NeighbourSearch();
  NeighbourSearch(const NeighbourSearch&) = delete;
  NeighbourSearch& operator=(const NeighbourSearch&) = delete;

  std::size_t size() const { return point_count_; }

  // For every point, how many points lie within `radius` of it, the point itself included
  // (|p - s| <= radius, inclusive). Allocates only the N counts.
  std::vector<std::uint32_t> count_within(double radius) const;
  // The same for points [first, first + count) only: count entries.
  std::vector<std::uint32_t> count_within(double radius, std::size_t first, std::size_t count) const;

  // An estimate of the sum of count_within(radius) from a sample of points spread through the
  // cloud: cheap when that sum is huge (cost: samples x neighbours), so a run can be refused
  // before the exact count, which costs about the sum itself.
  double estimate_pairs(double radius) const;

  // The lists of points [first, first + count) within `radius`, each in ascending id order. `counts` is what
  // count_within returned for the same radius; it sizes the arrays before any search runs.
  CsrLists lists_within(double radius, std::size_t first, std::size_t count,
                        const std::vector<std::uint32_t>& counts) const;

  // The same lists written into caller storage (a mapped device buffer, say): `offsets` has
  // count + 1 entries and `indices` the sum of counts[first .. first + count).
  void fill_lists(double radius, std::size_t first, std::size_t count, const std::vector<std::uint32_t>& counts,
                  std::uint64_t* offsets, std::uint32_t* indices) const;

  // For up to `max_samples` points spread evenly over the cloud: the mean distance to their k
  // nearest other points (duplicates count, at distance 0). Needs N >= k + 1.
  std::vector<double> mean_knn_distance(int k, std::size_t max_samples) const;

 private:
  struct Tree;
  // First point of each search block for `radius` (see the .cpp), then N.
  std::vector<std::size_t> block_starts(double radius) const;
  template <typename Visit>
  void for_each_point(double radius, std::size_t first, std::size_t count, Visit&& visit) const;

  std::size_t point_count_;
  std::vector<double> positions_;
  std::unique_ptr<Tree> tree_;
};

}  // namespace pnf::detail
