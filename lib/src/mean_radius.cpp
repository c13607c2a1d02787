#include "pnf/mean_radius.hpp"

#include <algorithm>

#include "mean_radius_internal.hpp"

namespace pnf {
namespace {

// The 4 nearest points of a square-grid sample are its edge neighbours at exactly the spacing.
constexpr int kSpacingNeighbours = 4;
// Enough samples for a median to a fraction of a percent; bounds the cost on huge clouds.
constexpr std::size_t kMaxSpacingSamples = 100000;

}  // namespace

namespace detail {

double estimate_mean_radius(const NeighbourSearch& search) {
  std::vector<double> distances = search.mean_knn_distance(kSpacingNeighbours, kMaxSpacingSamples);
  // A point whose 4 nearest are all duplicates of it says nothing about the spacing.
  distances.erase(std::remove(distances.begin(), distances.end(), 0.0), distances.end());
  if (distances.empty()) return 0;
  auto middle = distances.begin() + distances.size() / 2;
  std::nth_element(distances.begin(), middle, distances.end());
  return *middle;
}

}  // namespace detail

double estimate_mean_radius(const std::vector<Vec3>& positions) {
  detail::NeighbourSearch search(positions.empty() ? nullptr : positions[0].data(), positions.size());
  return detail::estimate_mean_radius(search);
}

}  // namespace pnf
