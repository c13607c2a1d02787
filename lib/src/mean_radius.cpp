#include "pnf/mean_radius.hpp"

#include <algorithm>
#include <string>
#include <utility>

#include "exact_sum.hpp"
#include "mean_radius_internal.hpp"
#include "pnf/error.hpp"
#include "spatial/spatial_order.hpp"

namespace pnf {
namespace detail {

double median_spacing(std::vector<double> distances) {
  distances.erase(std::remove(distances.begin(), distances.end(), 0.0), distances.end());
  if (distances.empty()) return 0;
  auto middle = distances.begin() + std::ptrdiff_t(distances.size() / 2);
  std::nth_element(distances.begin(), middle, distances.end());
  return *middle;
}

Vec3 axis_medians(const std::vector<double>& xyz) {
  const std::size_t n = xyz.size() / 3;
  return {axis_order_statistic(xyz, 0, n / 2), axis_order_statistic(xyz, 1, n / 2),
          axis_order_statistic(xyz, 2, n / 2)};
}

Vec3 sample_median(const Vec3ArrayView& positions, const std::vector<std::uint32_t>& curve) {
  const std::size_t n = positions.count, samples = std::min(n, kMaxSpacingSamples);
  std::vector<double> xyz(3 * samples);
  for (std::size_t s = 0; s < samples; ++s) {
    const Vec3 p = positions.at(curve[s * n / samples]);
    for (int c = 0; c < 3; ++c) xyz[3 * s + std::size_t(c)] = p[std::size_t(c)];
  }
  return axis_medians(xyz);
}

std::vector<double> centred_rows(const Vec3ArrayView& positions, const Vec3& centre,
                                 const std::vector<std::uint32_t>* order) {
  std::vector<double> rows(3 * positions.count);
  for (std::size_t k = 0; k < positions.count; ++k) {
    const Vec3 p = positions.at(order ? (*order)[k] : k);
    for (int c = 0; c < 3; ++c) rows[3 * k + std::size_t(c)] = p[std::size_t(c)] - centre[std::size_t(c)];
  }
  return rows;
}

void throw_cannot_estimate_mean_radius(std::size_t points) {
  throw Error(ErrorCode::invalid_input,
              "cannot estimate the mean surfel radius of " + std::to_string(points) +
                  " points (it needs at least 5 points, not most of them at one place); give the mean radius "
                  "explicitly or use absolute units");
}

double estimate_mean_radius(const SpatialIndex& index, const std::vector<std::uint32_t>* curve_order) {
  return median_spacing(index.mean_knn_distance(kSpacingNeighbours, kMaxSpacingSamples, curve_order));
}

MeanRadius resolve_mean_radius(double given, const ScalarArrayView& radii, std::size_t points,
                               const std::function<double()>& estimate) {
  if (given > 0) return {given, RadiusSource::given};
  if (!radii.empty()) {
    // Summed exactly, so that the mean has the same bits in any row order (and across ranks:
    // mpi/mean_radius_mpi.cpp).
    ExactSum sum;
    for (std::size_t i = 0; i < radii.count; ++i) sum.add(radii.get(i));
    return {sum.value() / double(radii.count), RadiusSource::property};
  }
  const double value = estimate();
  if (!(value > 0)) throw_cannot_estimate_mean_radius(points);
  return {value, RadiusSource::estimate};
}

}  // namespace detail

double estimate_mean_radius(const Vec3ArrayView& positions) {
  // The filter's frame: Morton order, re-centred on the samples' median (filter_engine.cpp), so
  // that both sample the same points and compute the same distances.
  const std::size_t n = positions.count;
  if (n == 0) return 0;
  const std::vector<std::uint32_t> order = detail::morton_order(positions);
  const detail::SpatialIndex index(detail::centred_rows(positions, detail::sample_median(positions, order), &order));
  return detail::estimate_mean_radius(index);
}

MeanRadius mean_radius(const CloudView& cloud, double given) {
  return detail::resolve_mean_radius(given, cloud.radii, cloud.size(),
                                     [&] { return estimate_mean_radius(cloud.positions); });
}

}  // namespace pnf
