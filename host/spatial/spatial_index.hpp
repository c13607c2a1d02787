// pnf's one spatial search: a FLANN kd-tree over a cloud's centred positions, answering every
// neighbour question the library asks (the filter's fixed-radius CSR lists, estimate_normals'
// k nearest, --auto's sampled k nearest, the mean-radius estimate). spatial_index.cpp is the only
// source file that includes FLANN.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "spatial/csr_lists.hpp"

namespace pnf::detail {

// Asked by the long searches below (count_within, fill_lists, lists_within, nearest_table) on the
// calling thread only, about every kPollSeconds (parallel_blocks.hpp), with the share of the work
// done in [0, 1]; returning false cancels: the worker threads stop at their next block and the
// search throws pnf::Error(cancelled). An exception it throws stops the workers the same way and
// is rethrown. Empty: never asked.
using WorkPoll = std::function<bool(double fraction)>;

// A kd-tree over N points, searched in parallel with OpenMP. All distances here are plain
// Euclidean distances in model units unless a name says "squared"; FLANN's own squared
// distances stay inside the .cpp except where a parameter is named squared_distances.
// Every search is exact (no approximation). Thread safety: const methods may run concurrently.
class SpatialIndex;

// The candidates of each search block of one list search (see spatial_index.cpp), kept by
// count_within for fill_lists, so that the fill (and, in a chunked run, every pass's refill)
// does not search the tree and sort again: on the dog setting those searches are about 2/3 of
// the count (docs/performance.md). Blocks of up to 256 points share one candidate set, so it
// takes about 3% of the lists' memory (44 MB for the dog's 1.3 GB, 220 MB for the 2M-point
// sigma_f 8 cloud's 6.5 GB); at most kMaxIds ids are kept, beyond that nothing is and the fill
// searches as before. Same lists either way. The engine counts them against its memory budget.
class BlockCandidates {
 public:
  static constexpr std::size_t kMaxIds = std::size_t(1) << 27;  // 512 MB
  // Whether a search for `radius` over points [first, first + count) can use these.
  bool covers(double radius, std::size_t first, std::size_t count) const {
    return complete_ && radius == radius_ && first >= first_ && first + count <= first_ + count_;
  }
  std::size_t bytes() const;

 private:
  friend class SpatialIndex;
  bool complete_ = false;
  double radius_ = 0;
  double block_extent_ = 0;
  std::size_t first_ = 0, count_ = 0;
  std::size_t first_block_ = 0;                     // global index of blocks_[0]
  std::vector<std::vector<std::uint32_t>> blocks_;  // per block, its sorted candidate ids
};

class SpatialIndex {
 public:
  // How the list searches (count_within, fill_lists) scan their candidates. For bench/ to compare
  // variants on one machine in one run; the defaults are the measured best (docs/performance.md).
  // Every variant gives the same lists: the exact test is the same double expression.
  struct ListTuning {
    double block_extent_in_radii = 1.0;  // a search block's largest extent along an axis, in radii
    bool wide_scan = true;               // the count's scan built for AVX-512 / AVX2 as well, chosen at run time
    bool avx512_scan = true;             // explicit AVX-512 scans (mask, popcount, compress) where the CPU has it
    bool avx2_scan = true;               // else explicit AVX2 scans (mask, popcount, table permute) where it has AVX2
  };
  void set_list_tuning(const ListTuning& tuning) { tuning_ = tuning; }
  // The candidates the list searches for `radius` test over points [first, first + count), for
  // bench/: their sum divided by the pairs is the candidates scanned per neighbour.
  std::size_t candidates_scanned(double radius, std::size_t first, std::size_t count) const;

  // How the points are laid out in memory; it sets whether the tree keeps its own copy.
  enum class Layout {
    // Points already sorted along a space-filling curve (morton_order): neighbours sit near each
    // other, so the tree searches the positions in place and makes no copy.
    curve_ordered,
    // Any other order: the tree keeps a copy of the points in its leaf order (FLANN's reorder),
    // so that a search reads memory forward. 24 bytes per point more.
    any_order,
  };

  // centred_positions: N by 3, row-major, model units, re-centred by the caller (on the bounding-
  // box centre, in double, so that far-away clouds lose no digits). Taken by move and owned.
  explicit SpatialIndex(std::vector<double> centred_positions, Layout layout = Layout::curve_ordered);
  ~SpatialIndex();
  SpatialIndex(const SpatialIndex&) = delete;
  SpatialIndex& operator=(const SpatialIndex&) = delete;

  std::size_t size() const { return point_count_; }
  // The positions the tree was built on (N by 3, centred), for the callers that read them.
  const std::vector<double>& positions() const { return positions_; }

  // ---- k nearest (exact) ----

  // The k nearest points of every point (query = the point itself), the point itself left out,
  // nearest first (ties in the tree's order, deterministic). Needs 1 <= k <= N - 1. Where
  // duplicates sit at distance 0 the point may come back in any slot or not at all; then the
  // farthest result is dropped instead. Runs on omp_get_max_threads() threads; the answer does
  // not depend on the count.
  NeighbourTable nearest_table(int k, const WorkPoll& poll = {}) const;

  // The k nearest points of point `point` (itself included when it is among them, which it is
  // unless k duplicates of it exist): ids[0 .. k) and their SQUARED distances, in no particular
  // order (but deterministic). One thread; callers spread their samples over threads. Needs
  // 1 <= k <= N. From k = 250, the points within a radius that holds k, then the k nearest of them
  // (FLANN's heap for so many cost most of --auto's estimate; spatial_index.cpp).
  void nearest_of_point(std::size_t point, std::size_t k, std::size_t* ids, double* squared_distances) const;

  // For up to `max_samples` points spread evenly over the cloud: the mean distance to their k
  // nearest other points (duplicates count, at distance 0). Sample s is point floor(s N / samples),
  // or with `order` (a permutation of the points) point order[floor(s N / samples)]. The value for
  // one point does not depend on the order the tree holds the points in (the k + 1 distances are
  // summed nearest first). Empty when N < k + 1 or max_samples is 0.
  std::vector<double> mean_knn_distance(int k, std::size_t max_samples,
                                        const std::vector<std::uint32_t>* order = nullptr) const;
  // mean_knn_distance's value for one point: the mean distance of point `point` to its k nearest
  // other points. Needs 1 <= k <= N - 1. One thread.
  double mean_nearest_distance(std::size_t point, int k) const;
  // The SQUARED distances of the k nearest points of point `point` (itself, at 0, among them
  // unless k duplicates of it exist), ascending. Needs 1 <= k <= N. One thread.
  std::vector<double> nearest_squared_distances(std::size_t point, int k) const;

  // ---- fixed radius (docs/method.md, "Reach": |p - s| <= radius, inclusive) ----

  // For every point, how many points lie within `radius` of it, the point itself included.
  // Allocates only the N counts.
  std::vector<std::uint32_t> count_within(double radius) const;
  // The same for points [first, first + count) only: count entries.
  // With `keep`, the blocks' candidates are kept there for fill_lists (see BlockCandidates).
  std::vector<std::uint32_t> count_within(double radius, std::size_t first, std::size_t count,
                                          const WorkPoll& poll = {}, BlockCandidates* keep = nullptr) const;

  // An estimate of the sum of count_within(radius) from a sample of points spread through the
  // cloud: cheap when that sum is huge (cost: samples x neighbours), so a run can be refused
  // before the exact count, which costs about the sum itself.
  double estimate_pairs(double radius) const;

  // The lists of points [first, first + count) within `radius`, each in ascending id order.
  // `counts` is what count_within returned for the same radius; it sizes the arrays before any
  // search runs.
  CsrLists lists_within(double radius, std::size_t first, std::size_t count, const std::vector<std::uint32_t>& counts,
                        const WorkPoll& poll = {}) const;

  // The same lists written into caller storage (a mapped device buffer, say): `offsets` has
  // count + 1 entries and `indices` the sum of counts[first .. first + count).
  void fill_lists(double radius, std::size_t first, std::size_t count, const std::vector<std::uint32_t>& counts,
                  std::uint64_t* offsets, std::uint32_t* indices, const WorkPoll& poll = {},
                  const BlockCandidates* reuse = nullptr) const;

 private:
  struct Tree;
  // First point of each search block for `radius` (see the .cpp), then N.
  std::vector<std::size_t> block_starts(double radius) const;
  template <typename Visit>
  void for_each_point(double radius, std::size_t first, std::size_t count, const WorkPoll& poll, Visit&& visit,
                      const BlockCandidates* reuse = nullptr, BlockCandidates* keep = nullptr) const;

  std::vector<double> positions_;
  std::size_t point_count_;
  ListTuning tuning_;
  std::unique_ptr<Tree> tree_;
};

}  // namespace pnf::detail
