#include "spatial/spatial_index.hpp"

// The only FLANN include of pnf; only the two headers needed (flann/flann.hpp pulls in every
// index type).
#include <flann/algorithms/dist.h>
#include <flann/algorithms/kdtree_single_index.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <numeric>
#include <string>
#include <utility>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "pnf/error.hpp"
#include "spatial/candidate_scan.hpp"
#include "spatial/parallel_blocks.hpp"

namespace pnf::detail {
namespace {

using Distance = flann::L2<double>;  // NB: FLANN's L2 is the SQUARED Euclidean distance
using Clock = std::chrono::steady_clock;

// Hands each point a radius search finds to `collect` (its squared distance and id): the ids of
// a candidate search, or the ids with their distances. The search's limit stays fixed.
template <class Collect>
class CollectingResultSet : public flann::ResultSet<double> {
 public:
  CollectingResultSet(double squared_limit, Collect collect)
      : squared_limit_(squared_limit), collect_(std::move(collect)) {}
  bool full() const override { return true; }
  void addPoint(double squared_distance, size_t index) override { collect_(squared_distance, index); }
  double worstDist() const override { return squared_limit_; }

 private:
  double squared_limit_;
  Collect collect_;
};

// A candidate search's ids, appended to `out`.
auto collect_ids(double squared_limit, std::vector<std::uint32_t>& out) {
  return CollectingResultSet(squared_limit, [&out](double, size_t index) { out.push_back(std::uint32_t(index)); });
}

// FLANN keeps a k-nearest search's best in a heap from k = 250 up (its KNN_HEAP_THRESHOLD), and
// that heap's upkeep was most of --auto's estimate, whose scales reach 1024-4096 neighbours. From
// this k on, nearest_of_point takes the k nearest from the points within a radius that holds them:
// the radius of the nearest k / kGuessShare points, widened as far as a surface would need to
// hold k (its points grow with the radius squared) times kGuessAreaMargin, and widened again
// (kWidening in the radius squared) until it holds k. A volume fills faster than a surface (more
// candidates, still exact), a curve slower (a widening or two).
constexpr std::size_t kRadiusSearchFromK = 250;
constexpr std::size_t kGuessShare = 16;
constexpr double kGuessAreaMargin = 1.5;
constexpr double kWidening = 4;
constexpr int kMaxWidenings = 8;  // then, or with no radius to widen (duplicates), FLANN's own search

flann::SearchParams exact_search() {
  flann::SearchParams params;
  params.eps = 0;  // exact: no approximation in the neighbourhood
  params.sorted = false;
  return params;
}

// Points are searched a block at a time: consecutive points along the curve whose bounding box
// is at most ListTuning::block_extent_in_radii (default 1) of the radius across. One kd-tree
// search per block gathers every point within radius + the block's half-diagonal (a superset of
// each member's neighbours);
// each member then keeps the candidates within the radius, checked exactly. This replaces a
// tree descent per point by a short, vectorisable scan, and gives ascending (memory-ordered)
// lists. Blocks one radius across keep the candidates near three times the neighbours on a
// surface; measured in bench/ against half a radius: 35% less time for count + fill.
constexpr std::size_t kMaxBlockPoints = 256;
// Widens the candidate search a hair beyond radius + half-diagonal against rounding.
constexpr double kCandidateMargin = 1e-9;

// FLANN's default leaf size. Measured against 4 to 32 on the filter's lists: within a few percent;
// the block search below does most of the work.
constexpr int kLeafMaxSize = 10;

// Queries of nearest_table go to FLANN in blocks of this many points: its size_t index and
// distance buffers (16 bytes per neighbour) stay at a few MB for any N, each block still keeps
// every thread busy, and the calling thread polls between blocks, so a cancel waits for one
// block at most (at k = 200, 65536 queries took over 10 s in the sanitizer build).
constexpr std::size_t kQueryBlock = std::size_t{1} << 12;

}  // namespace

struct SpatialIndex::Tree {
  flann::Matrix<double> data;
  flann::KDTreeSingleIndex<Distance> index;
  // reorder = false searches the caller's (curve-ordered) positions in place; true makes FLANN
  // copy them in leaf order. The tree and every answer are the same either way (FLANN visits the
  // same leaves in the same order); only the memory read differs.
  Tree(double* positions, std::size_t n, bool reorder)
      : data(positions, n, 3), index(data, flann::KDTreeSingleIndexParams(kLeafMaxSize, reorder)) {
    index.buildIndex();
  }
};

SpatialIndex::SpatialIndex(std::vector<double> centred_positions, Layout layout)
    : positions_(std::move(centred_positions)), point_count_(positions_.size() / 3) {
  if (positions_.size() != 3 * point_count_) {
    throw Error(ErrorCode::invalid_input, "internal error: SpatialIndex needs N by 3 positions, got " +
                                              std::to_string(positions_.size()) + " values");
  }
  if (point_count_ > 0) {
    tree_ = std::make_unique<Tree>(positions_.data(), point_count_, layout == Layout::any_order);
  }
}

SpatialIndex::~SpatialIndex() = default;

std::vector<std::size_t> SpatialIndex::block_starts(double radius) const {
  std::vector<std::size_t> starts;
  const double max_extent = tuning_.block_extent_in_radii * radius;
  std::size_t i = 0;
  while (i < point_count_) {
    starts.push_back(i);
    double lo[3], hi[3];
    for (int k = 0; k < 3; ++k) lo[k] = hi[k] = positions_[3 * i + k];
    std::size_t j = i + 1;
    for (; j < point_count_ && j - i < kMaxBlockPoints; ++j) {
      double nlo[3], nhi[3];
      bool fits = true;
      for (int k = 0; k < 3; ++k) {
        nlo[k] = std::min(lo[k], positions_[3 * j + k]);
        nhi[k] = std::max(hi[k], positions_[3 * j + k]);
        fits = fits && nhi[k] - nlo[k] <= max_extent;
      }
      if (!fits) break;
      for (int k = 0; k < 3; ++k) {
        lo[k] = nlo[k];
        hi[k] = nhi[k];
      }
    }
    i = j;
  }
  starts.push_back(point_count_);
  return starts;
}

// Calls visit(point, candidate ids, their coordinates as x, y, z arrays) for every point of
// [first, first + count), block by block in parallel; visit keeps the candidates within radius.
// `visit` gets the point, the block's candidate ids and coordinates, and a scratch array as long
// as the candidates.
template <typename Visit>
void SpatialIndex::for_each_point(double radius, std::size_t first, std::size_t count, const WorkPoll& poll,
                                  Visit&& visit, const BlockCandidates* reuse, BlockCandidates* keep) const {
  const std::vector<std::size_t> starts = block_starts(radius);
  const std::size_t end = first + count;
  // Blocks that overlap [first, end).
  std::size_t b0 = std::upper_bound(starts.begin(), starts.end(), first) - starts.begin() - 1;
  std::size_t b1 = std::lower_bound(starts.begin(), starts.end(), end) - starts.begin();
  const flann::SearchParams params = exact_search();
  if (reuse && !(reuse->covers(radius, first, count) && reuse->block_extent_ == tuning_.block_extent_in_radii)) {
    reuse = nullptr;
  }
  std::atomic<std::size_t> kept{0};
  std::atomic<bool> overflow{false};
  if (keep) {
    *keep = BlockCandidates{};
    keep->radius_ = radius;
    keep->block_extent_ = tuning_.block_extent_in_radii;
    keep->first_ = first;
    keep->count_ = count;
    keep->first_block_ = b0;
    keep->blocks_.resize(b1 - b0);
  }
  struct Scratch {
    std::vector<std::uint32_t> ids, scratch;
    std::vector<double> cx, cy, cz;
  };
  parallel_blocks(
      b1 - b0, poll, [] { return Scratch{}; },
      [&](Scratch& s, std::size_t b) {
        const std::size_t begin = starts[b0 + b], stop = starts[b0 + b + 1];
        double lo[3], hi[3], centre[3], half_diagonal2 = 0;
        for (int k = 0; k < 3; ++k) lo[k] = hi[k] = positions_[3 * begin + k];
        for (std::size_t i = begin; i < stop; ++i) {
          for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], positions_[3 * i + k]);
            hi[k] = std::max(hi[k], positions_[3 * i + k]);
          }
        }
        for (int k = 0; k < 3; ++k) {
          centre[k] = 0.5 * (lo[k] + hi[k]);
          half_diagonal2 += 0.25 * (hi[k] - lo[k]) * (hi[k] - lo[k]);
        }
        if (reuse) {
          const std::vector<std::uint32_t>& kept_ids = reuse->blocks_[b0 + b - reuse->first_block_];
          s.ids.assign(kept_ids.begin(), kept_ids.end());
        } else {
          const double reach = (radius + std::sqrt(half_diagonal2)) * (1 + kCandidateMargin);
          s.ids.clear();
          auto result = collect_ids(reach * reach, s.ids);
          tree_->index.findNeighbors(result, centre, params);
          std::sort(s.ids.begin(), s.ids.end());  // ascending ids: lists that walk memory forward
        }
        if (keep && !overflow.load(std::memory_order_relaxed)) {
          if (kept.fetch_add(s.ids.size(), std::memory_order_relaxed) + s.ids.size() > BlockCandidates::kMaxIds) {
            overflow = true;
          } else {
            keep->blocks_[b] = s.ids;  // one exact allocation a block, no growing vector to copy
          }
        }
        // Room for the AVX-512 (16 ids) and AVX2 (8) compactions' full-width stores.
        s.scratch.resize(s.ids.size() + 16);
        s.cx.resize(s.ids.size());
        s.cy.resize(s.ids.size());
        s.cz.resize(s.ids.size());
        for (std::size_t c = 0; c < s.ids.size(); ++c) {
          s.cx[c] = positions_[3 * std::size_t(s.ids[c])];
          s.cy[c] = positions_[3 * std::size_t(s.ids[c]) + 1];
          s.cz[c] = positions_[3 * std::size_t(s.ids[c]) + 2];
        }
        for (std::size_t i = std::max(begin, first); i < std::min(stop, end); ++i) {
          visit(i, s.ids, s.cx, s.cy, s.cz, s.scratch);
        }
      });
  if (keep) {
    keep->complete_ = !overflow;
    if (overflow) *keep = BlockCandidates{};
  }
}

std::size_t BlockCandidates::bytes() const {
  std::size_t ids = 0;
  for (const auto& v : blocks_) ids += v.capacity();
  return ids * sizeof(std::uint32_t) + blocks_.capacity() * sizeof(blocks_[0]);
}

std::vector<std::uint32_t> SpatialIndex::count_within(double radius) const {
  return count_within(radius, 0, point_count_);
}

std::vector<std::uint32_t> SpatialIndex::count_within(double radius, std::size_t first, std::size_t count,
                                                      const WorkPoll& poll, BlockCandidates* keep) const {
  std::vector<std::uint32_t> counts(count);
  const double radius2 = radius * radius;
  for_each_point(
      radius, first, count, poll,
      [&](std::size_t i, const std::vector<std::uint32_t>& ids, const std::vector<double>& cx,
          const std::vector<double>& cy, const std::vector<double>& cz, std::vector<std::uint32_t>&) {
        const double px = positions_[3 * i], py = positions_[3 * i + 1], pz = positions_[3 * i + 2];
        const Candidates c{cx.data(), cy.data(), cz.data(), ids.size()};
        counts[i - first] = count_candidates_within(c, px, py, pz, radius2, tuning_);
      },
      nullptr, keep);
  return counts;
}

std::size_t SpatialIndex::candidates_scanned(double radius, std::size_t first, std::size_t count) const {
  std::vector<std::uint32_t> scanned(count);
  for_each_point(
      radius, first, count, {},
      [&](std::size_t i, const std::vector<std::uint32_t>& ids, const std::vector<double>&, const std::vector<double>&,
          const std::vector<double>&, std::vector<std::uint32_t>&) { scanned[i - first] = std::uint32_t(ids.size()); });
  return std::accumulate(scanned.begin(), scanned.end(), std::size_t(0));
}

CsrLists SpatialIndex::lists_within(double radius, std::size_t first, std::size_t count,
                                    const std::vector<std::uint32_t>& counts, const WorkPoll& poll) const {
  CsrLists lists;
  lists.first_point = first;
  lists.point_count = count;
  std::size_t pairs = 0;
  for (std::size_t k = 0; k < count; ++k) pairs += counts[first + k];
  lists.offsets.resize(count + 1);
  lists.indices.resize(pairs);
  fill_lists(radius, first, count, counts, lists.offsets.data(), lists.indices.data(), poll);
  return lists;
}

void SpatialIndex::fill_lists(double radius, std::size_t first, std::size_t count,
                              const std::vector<std::uint32_t>& counts, std::uint64_t* offsets, std::uint32_t* indices,
                              const WorkPoll& poll, const BlockCandidates* reuse) const {
  offsets[0] = 0;
  for (std::size_t k = 0; k < count; ++k) offsets[k + 1] = offsets[k] + counts[first + k];
  const double radius2 = radius * radius;
  std::atomic<bool> mismatch{false};
  for_each_point(
      radius, first, count, poll,
      [&](std::size_t i, const std::vector<std::uint32_t>& ids, const std::vector<double>& cx,
          const std::vector<double>& cy, const std::vector<double>& cz, std::vector<std::uint32_t>& scratch) {
        const double px = positions_[3 * i], py = positions_[3 * i + 1], pz = positions_[3 * i + 2];
        // Branch-free compaction into scratch (a member or not is a coin toss near the
        // boundary, which a branch predicts badly), then one copy into the list.
        const Candidates c{cx.data(), cy.data(), cz.data(), ids.size()};
        const std::size_t written =
            compact_candidates_within(c, ids.data(), px, py, pz, radius2, tuning_, scratch.data());
        const std::size_t capacity = offsets[i - first + 1] - offsets[i - first];
        if (written != capacity) {
          mismatch = true;
          return;
        }
        std::copy(scratch.begin(), scratch.begin() + written, indices + offsets[i - first]);
      },
      reuse);
  if (mismatch) {
    // The same exact test ran twice on the same data; a different count is a bug, not bad data.
    throw Error(ErrorCode::invalid_input, "internal error: neighbour search gave different counts on two runs");
  }
}

double SpatialIndex::estimate_pairs(double radius) const {
  // Enough samples to see a dense region covering a few percent of the cloud.
  constexpr std::size_t kSamples = 256;
  if (point_count_ == 0) return 0;
  const std::size_t samples = std::min(kSamples, point_count_);
  std::vector<double> sampled(samples);
  const flann::SearchParams params = exact_search();
  const double radius2 = radius * radius;
  const auto n = static_cast<std::int64_t>(samples);
#pragma omp parallel
  {
    std::vector<std::uint32_t> ids;
#pragma omp for schedule(dynamic, 1)
    for (std::int64_t s = 0; s < n; ++s) {
      const std::size_t i = static_cast<std::size_t>(s) * point_count_ / samples;
      ids.clear();
      auto result = collect_ids(radius2 * (1 + kCandidateMargin), ids);
      tree_->index.findNeighbors(result, &positions_[3 * i], params);
      sampled[s] = double(ids.size());
    }
  }
  double sum = 0;
  for (double v : sampled) sum += v;
  return sum / double(samples) * double(point_count_);
}

std::vector<double> SpatialIndex::mean_knn_distance(int k, std::size_t max_samples,
                                                    const std::vector<std::uint32_t>* order) const {
  if (point_count_ < static_cast<std::size_t>(k) + 1 || max_samples == 0) return {};
  const std::size_t samples = std::min(max_samples, point_count_);
  std::vector<double> out(samples);
  const auto n = static_cast<std::int64_t>(samples);
#pragma omp parallel for schedule(dynamic, 256)
  for (std::int64_t s = 0; s < n; ++s) {
    std::size_t i = static_cast<std::size_t>(s) * point_count_ / samples;
    if (order != nullptr) i = (*order)[i];
    out[s] = mean_nearest_distance(i, k);
  }
  return out;
}

std::vector<double> SpatialIndex::nearest_squared_distances(std::size_t point, int k) const {
  flann::KNNResultSet<double> result(k);
  tree_->index.findNeighbors(result, &positions_[3 * point], exact_search());
  std::vector<size_t> ids(k);
  std::vector<double> squared(k);
  result.copy(ids.data(), squared.data(), k, false);  // the result set keeps them ascending
  return squared;
}

double SpatialIndex::mean_nearest_distance(std::size_t point, int k) const {
  // k + 1 nearest: the point itself (or a duplicate of it) comes back at distance 0, so the sum
  // of all k + 1 distances, nearest first, is the sum over its k nearest others.
  double sum = 0;
  for (double d2 : nearest_squared_distances(point, k + 1)) sum += std::sqrt(d2);
  return sum / k;
}

NeighbourTable SpatialIndex::nearest_table(int k, const WorkPoll& poll) const {
  flann::SearchParams search;
  // Exact search; the single kd-tree is exact anyway, but say so rather than rely on it.
  search.checks = flann::FLANN_CHECKS_UNLIMITED;
  search.eps = 0.0f;
  search.sorted = true;
#ifdef _OPENMP
  // FLANN spreads the queries of one call over this many threads; each query's answer is
  // computed by one thread alone, so it does not depend on the count.
  search.cores = omp_get_max_threads();
#else
  search.cores = 1;
#endif

  // Each point's own entry is asked for too (k + 1 results) and then dropped.
  const std::size_t count = point_count_;
  const auto wanted = static_cast<std::size_t>(k) + 1;
  NeighbourTable table;
  table.point_count = count;
  table.k = k;
  table.indices.resize(count * static_cast<std::size_t>(k));
  std::vector<std::size_t> found(std::min(count, kQueryBlock) * wanted);
  // FLANN's L2 distances are SQUARED Euclidean distances; they are only needed for the sort
  // order, which FLANN has already applied, and are not read here.
  std::vector<double> squared_distances(found.size());
  // FLANN's query matrix is of non-const elements; it only reads them.
  double* queries_data = const_cast<double*>(positions_.data());

  Clock::time_point last_poll{};  // the first block asks
  for (std::size_t first = 0; first < count; first += kQueryBlock) {
    // FLANN spreads each block over the threads itself; between blocks this (calling) thread asks.
    if (poll && std::chrono::duration<double>(Clock::now() - last_poll).count() >= kPollSeconds) {
      if (!poll(double(first) / double(count))) {
        throw Error(ErrorCode::cancelled, "cancelled while searching neighbours");
      }
      last_poll = Clock::now();
    }
    const std::size_t rows = std::min(kQueryBlock, count - first);
    const flann::Matrix<double> queries(queries_data + first * 3, rows, 3);
    flann::Matrix<std::size_t> found_matrix(found.data(), rows, wanted);
    flann::Matrix<double> distance_matrix(squared_distances.data(), rows, wanted);
    tree_->index.knnSearch(queries, found_matrix, distance_matrix, wanted, search);

    for (std::size_t r = 0; r < rows; ++r) {
      const std::size_t point = first + r;
      // The point itself is normally the first result, but where duplicates sit at distance 0 it
      // may be further down or missing; then the farthest result is dropped instead.
      const std::size_t* results = found.data() + r * wanted;
      int* row = table.indices.data() + point * static_cast<std::size_t>(k);
      std::size_t filled = 0;
      for (std::size_t slot = 0; slot < wanted && filled < static_cast<std::size_t>(k); ++slot) {
        if (results[slot] != point) row[filled++] = static_cast<int>(results[slot]);
      }
    }
  }
  return table;
}

void SpatialIndex::nearest_of_point(std::size_t point, std::size_t k, std::size_t* ids,
                                    double* squared_distances) const {
  const double* query = &positions_[3 * point];
  if (k >= kRadiusSearchFromK) {
    flann::KNNResultSet<double> guess(k / kGuessShare);
    tree_->index.findNeighbors(guess, query, exact_search());
    double limit = guess.worstDist() * double(kGuessShare) * kGuessAreaMargin;
    std::vector<std::pair<double, std::size_t>> found;
    found.reserve(2 * k);
    for (int widening = 0; limit > 0 && widening <= kMaxWidenings; ++widening, limit *= kWidening) {
      found.clear();
      CollectingResultSet within(
          limit, [&found](double squared_distance, size_t index) { found.emplace_back(squared_distance, index); });
      tree_->index.findNeighbors(within, query, exact_search());
      if (found.size() < k) continue;
      // Every point nearer than the limit was found, so the k nearest of them are the cloud's.
      std::nth_element(found.begin(), found.begin() + std::ptrdiff_t(k - 1), found.end());
      for (std::size_t j = 0; j < k; ++j) {
        squared_distances[j] = found[j].first;
        ids[j] = found[j].second;
      }
      return;
    }
  }
  flann::SearchParams search;
  search.checks = flann::FLANN_CHECKS_UNLIMITED;
  search.eps = 0.0f;
  search.sorted = false;
  search.cores = 1;  // the caller spreads its samples over threads instead
  const flann::Matrix<double> query_matrix(const_cast<double*>(query), 1, 3);
  flann::Matrix<std::size_t> id_matrix(ids, 1, k);
  flann::Matrix<double> distance_matrix(squared_distances, 1, k);
  tree_->index.knnSearch(query_matrix, id_matrix, distance_matrix, k, search);
}

}  // namespace pnf::detail
