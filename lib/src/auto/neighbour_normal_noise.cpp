// --auto's noise of the input normals from their neighbours' normals (neighbour_normal_noise.hpp).
#include "neighbour_normal_noise.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "geometry.hpp"
#include "sample_neighbourhoods.hpp"

namespace pnf::detail {
namespace {

// A linear field over the tangent plane has 3 coefficients per component; two of a unit
// normal's components carry its (tangent) error, so the residuals hold 2 (m - 3) degrees of
// freedom of the per-axis variance: (m - 3) of the total.
constexpr int kFieldCoefficients = 3;

// A sample whose gradient's own noise takes out more than half the noise from its residuals
// (the position noise wide against its neighbours' spread along the surface) would have its
// estimate more than doubled by the division: too uncertain, left out.
constexpr double kMinNoiseLeft = 0.5;

// The median of a chi-square of k degrees of freedom over its mean, 1 - 2/(9k) cubed
// (Wilson-Hilferty; within 0.1% from k = 10).
double chi_square_median_per_mean(double k) { return std::pow(1 - 2 / (9 * k), 3); }

// Point i's input normal made unit; false where it has none (zero, NaN or infinite).
bool unit_normal(const CloudView& cloud, std::size_t i, Vec3& n) {
  n = cloud.normals.at(i);
  const double length = geometry::norm(n);
  if (!(length > 0) || !std::isfinite(length)) return false;
  n = geometry::normalized(n);
  return true;
}

// p_j - p_i in the centred positions.
Vec3 offset(const std::vector<double>& centred, std::size_t i, std::size_t j) {
  return {centred[3 * j] - centred[3 * i], centred[3 * j + 1] - centred[3 * i + 1],
          centred[3 * j + 2] - centred[3 * i + 2]};
}

// One sample's noise variance (radians^2), or NaN where its neighbourhood cannot be fitted.
double sample_variance(const std::vector<double>& centred, const CloudView& cloud, const std::size_t* ids, int count,
                       double position_noise) {
  const std::size_t self = ids[0];
  Vec3 own;
  if (!unit_normal(cloud, self, own)) return NAN;
  Vec3 a, b;
  geometry::tangent_basis(own, a, b);
  Eigen::Matrix<double, Eigen::Dynamic, kFieldCoefficients> x(count, kFieldCoefficients);
  Eigen::Matrix<double, Eigen::Dynamic, 3> y(count, 3);
  int rows = 0;
  for (int k = 0; k < count; ++k) {
    const std::size_t j = ids[k];
    Vec3 n;
    if (!unit_normal(cloud, j, n)) continue;
    const double sign = geometry::dot(n, own) < 0 ? -1.0 : 1.0;
    const Vec3 d = offset(centred, self, j);
    x.row(rows) << 1, geometry::dot(d, a), geometry::dot(d, b);
    for (int c = 0; c < 3; ++c) y(rows, c) = sign * n[std::size_t(c)];
    ++rows;
  }
  if (rows <= kFieldCoefficients + 1) return NAN;
  const auto xs = x.topRows(rows);
  const auto ys = y.topRows(rows);
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(xs);
  if (qr.rank() < kFieldCoefficients) return NAN;
  const Eigen::MatrixXd field = qr.solve(Eigen::MatrixXd(ys));  // 3 x 3: offset, then the gradient along a, b
  const double residual = (ys - xs * field).squaredNorm() / double(rows - kFieldCoefficients);
  const double gradient = field.bottomRows(2).squaredNorm();
  // The fitted gradient carries the noise too: its squared norm averages the true one plus the
  // noise variance times the trace of (X^T X)^-1 over the gradient's terms, so the correction
  // above takes out that much noise as well; divided by what it leaves.
  const Eigen::Matrix<double, kFieldCoefficients, kFieldCoefficients> inverse = (xs.transpose() * xs).inverse();
  const double left = 1 - (inverse(1, 1) + inverse(2, 2)) * position_noise * position_noise;
  if (!(left > kMinNoiseLeft)) return NAN;
  return (residual - gradient * position_noise * position_noise) / left;
}

}  // namespace

double neighbour_normal_noise_deg(const std::vector<double>& centred, const CloudView& cloud,
                                  const SampleNeighbourhoods& nearest, double position_noise) {
  if (!cloud.has_normals() || nearest.neighbours <= kNoiseNeighbours) return -1;
  std::vector<double> variances(nearest.samples(), NAN);
#pragma omp parallel for schedule(dynamic, 64)
  for (long long s = 0; s < static_cast<long long>(nearest.samples()); ++s) {
    variances[std::size_t(s)] =
        sample_variance(centred, cloud, nearest.ids_of(std::size_t(s)), kNoiseNeighbours, position_noise);
  }
  const std::size_t all = variances.size();
  variances.erase(std::remove_if(variances.begin(), variances.end(), [](double v) { return std::isnan(v); }),
                  variances.end());
  if (variances.empty() || 2 * variances.size() < all) return -1;
  auto middle = variances.begin() + std::ptrdiff_t(variances.size() / 2);
  std::nth_element(variances.begin(), middle, variances.end());
  const double dof = 2.0 * (kNoiseNeighbours - kFieldCoefficients);
  const double variance = std::max(*middle, 0.0) / chi_square_median_per_mean(dof);
  return std::sqrt(variance) * 180 / geometry::kPi;
}

double chord_normal_noise_deg(const std::vector<double>& centred, const CloudView& cloud,
                              const SampleNeighbourhoods& nearest) {
  if (!cloud.has_normals() || nearest.neighbours <= kChordNeighbours) return -1;
  std::vector<double> chords;
  chords.reserve(nearest.samples() * kChordNeighbours);
  for (std::size_t s = 0; s < nearest.samples(); ++s) {
    const std::size_t* ids = nearest.ids_of(s);
    const std::size_t self = ids[0];
    Vec3 own;
    if (!unit_normal(cloud, self, own)) continue;
    for (int k = 1; k <= kChordNeighbours; ++k) {
      const std::size_t j = ids[k];
      Vec3 n;
      if (!unit_normal(cloud, j, n)) continue;
      const double sign = geometry::dot(n, own) < 0 ? -1.0 : 1.0;
      const Vec3 d = offset(centred, self, j);
      const double length = geometry::norm(d);
      if (!(length > 0)) continue;  // a duplicate point has no chord
      const Vec3 sum = {own[0] + sign * n[0], own[1] + sign * n[1], own[2] + sign * n[2]};
      chords.push_back(std::abs(geometry::dot(d, sum)) / (2 * length));
    }
  }
  if (chords.empty()) return -1;
  auto middle = chords.begin() + std::ptrdiff_t(chords.size() / 2);
  std::nth_element(chords.begin(), middle, chords.end());
  constexpr double kGaussianMedianAbsolute = 0.6745;  // the median of |x| over x's SD, x Gaussian
  const double spread = *middle / kGaussianMedianAbsolute;
  return 2 * spread * 180 / geometry::kPi;
}

}  // namespace pnf::detail
