#include "neighbour_lists.hpp"

#include <flann/flann.hpp>

#include <atomic>
#include <cmath>
#include <limits>
#include <string>

#include "pnf/error.hpp"

namespace pnf::detail {
namespace {

using Distance = flann::L2<double>;  // NB: FLANN's L2 is the SQUARED Euclidean distance

// FLANN keeps a leaf point only when its squared distance is strictly below worstDist();
// SPEC's neighbourhood is inclusive (|p - s| <= 2 sigma_f), so the limit is nudged one ulp up.
double inclusive_squared_limit(double radius) {
  return std::nextafter(radius * radius, std::numeric_limits<double>::infinity());
}

class CountingResultSet : public flann::ResultSet<double> {
 public:
  explicit CountingResultSet(double squared_limit) : squared_limit_(squared_limit) {}
  bool full() const override { return true; }
  void addPoint(double, size_t) override { ++count_; }
  double worstDist() const override { return squared_limit_; }
  std::size_t count() const { return count_; }

 private:
  double squared_limit_;
  std::size_t count_ = 0;
};

// Writes neighbour ids straight into a slot of the CSR array, sized by a previous count.
class WritingResultSet : public flann::ResultSet<double> {
 public:
  WritingResultSet(double squared_limit, std::uint32_t* out, std::size_t capacity)
      : squared_limit_(squared_limit), out_(out), capacity_(capacity) {}
  bool full() const override { return true; }
  void addPoint(double, size_t index) override {
    if (written_ < capacity_) out_[written_] = static_cast<std::uint32_t>(index);
    ++written_;
  }
  double worstDist() const override { return squared_limit_; }
  std::size_t written() const { return written_; }

 private:
  double squared_limit_;
  std::uint32_t* out_;
  std::size_t capacity_;
  std::size_t written_ = 0;
};

flann::SearchParams exact_search() {
  flann::SearchParams params;
  params.eps = 0;  // exact: no approximation in the neighbourhood
  params.sorted = false;
  return params;
}

}  // namespace

struct NeighbourSearch::Tree {
  flann::Matrix<double> data;
  flann::KDTreeSingleIndex<Distance> index;
  Tree(double* positions, std::size_t n)
      : data(positions, n, 3), index(data, flann::KDTreeSingleIndexParams(/*leaf_max_size=*/10, /*reorder=*/true)) {
    index.buildIndex();
  }
};

NeighbourSearch::NeighbourSearch(const double* positions, std::size_t point_count)
    : point_count_(point_count), positions_(positions, positions + 3 * point_count) {
  if (point_count_ > 0) tree_ = std::make_unique<Tree>(positions_.data(), point_count_);
}

NeighbourSearch::~NeighbourSearch() = default;

std::vector<std::uint32_t> NeighbourSearch::count_within(double radius) const {
  std::vector<std::uint32_t> counts(point_count_);
  const double limit = inclusive_squared_limit(radius);
  const flann::SearchParams params = exact_search();
  const auto n = static_cast<std::int64_t>(point_count_);
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::int64_t i = 0; i < n; ++i) {
    CountingResultSet result(limit);
    tree_->index.findNeighbors(result, &positions_[3 * i], params);
    counts[i] = static_cast<std::uint32_t>(result.count());
  }
  return counts;
}

CsrLists NeighbourSearch::lists_within(double radius, std::size_t first, std::size_t count,
                                       const std::vector<std::uint32_t>& counts) const {
  CsrLists lists;
  lists.first_point = first;
  lists.point_count = count;
  std::size_t pairs = 0;
  for (std::size_t k = 0; k < count; ++k) pairs += counts[first + k];
  lists.offsets.resize(count + 1);
  lists.indices.resize(pairs);
  fill_lists(radius, first, count, counts, lists.offsets.data(), lists.indices.data());
  return lists;
}

void NeighbourSearch::fill_lists(double radius, std::size_t first, std::size_t count,
                                 const std::vector<std::uint32_t>& counts, std::uint64_t* offsets,
                                 std::uint32_t* indices) const {
  offsets[0] = 0;
  for (std::size_t k = 0; k < count; ++k) offsets[k + 1] = offsets[k] + counts[first + k];
  const double limit = inclusive_squared_limit(radius);
  const flann::SearchParams params = exact_search();
  std::atomic<bool> mismatch{false};
  const auto n = static_cast<std::int64_t>(count);
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::int64_t k = 0; k < n; ++k) {
    std::size_t capacity = offsets[k + 1] - offsets[k];
    WritingResultSet result(limit, indices + offsets[k], capacity);
    tree_->index.findNeighbors(result, &positions_[3 * (first + k)], params);
    if (result.written() != capacity) mismatch = true;
  }
  if (mismatch) {
    // The same exact search ran twice on the same tree; a different count is a bug, not bad data.
    throw Error(ErrorCode::invalid_input, "internal error: neighbour search gave different counts on two runs");
  }
}

std::vector<double> NeighbourSearch::mean_knn_distance(int k, std::size_t max_samples) const {
  if (point_count_ < static_cast<std::size_t>(k) + 1 || max_samples == 0) return {};
  const std::size_t samples = std::min(max_samples, point_count_);
  std::vector<double> out(samples);
  const flann::SearchParams params = exact_search();
  const auto n = static_cast<std::int64_t>(samples);
#pragma omp parallel for schedule(dynamic, 256)
  for (std::int64_t s = 0; s < n; ++s) {
    std::size_t i = static_cast<std::size_t>(s) * point_count_ / samples;
    // k + 1 nearest: the point itself (or a duplicate of it) comes back at distance 0, so the
    // sum of all k + 1 distances is the sum over its k nearest others.
    flann::KNNResultSet<double> result(k + 1);
    tree_->index.findNeighbors(result, &positions_[3 * i], params);
    std::vector<size_t> ids(k + 1);
    std::vector<double> squared(k + 1);
    result.copy(ids.data(), squared.data(), k + 1, false);
    double sum = 0;
    for (double d2 : squared) sum += std::sqrt(d2);
    out[s] = sum / k;
  }
  return out;
}

}  // namespace pnf::detail
