// --auto's judge of a normal field against the surface its positions carry (surface_judge.hpp).
#include "surface_judge.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "geometry.hpp"
#include "spatial/spatial_index.hpp"

namespace pnf::detail {
namespace {

// Reweighting steps of the fit: from the judged normal's own plane, the weights settle on one
// sheet within a few steps (the score moved by under 1% after the fifth on the real meshes).
constexpr int kReweightSteps = 5;
// A quadric has 6 coefficients; twice as many points at least.
constexpr int kMinNeighbours = 12;

// The angle (radians) between `n` and the normal of the quadric fitted in n's frame to the
// sample's neighbours (`offsets`, `count` rows), each weighted by a Gaussian of width `width` on
// its residual, starting from the residual to n's plane.
double error_in_frame(const double* offsets, int count, Eigen::Vector3d n, double width) {
  const double length = n.norm();
  if (!(length > 0) || !std::isfinite(length)) return 0;
  n /= length;
  Vec3 a, b;
  geometry::tangent_basis({n.x(), n.y(), n.z()}, a, b);
  const Eigen::Vector3d t1(a[0], a[1], a[2]), t2(b[0], b[1], b[2]);
  // Coordinates in units of the farthest neighbour, for a well-conditioned system.
  double reach = 0;
  for (int k = 0; k < count; ++k) {
    const Eigen::Vector3d o(offsets[3 * k], offsets[3 * k + 1], offsets[3 * k + 2]);
    reach = std::max(reach, o.norm());
  }
  if (!(reach > 0)) return 0;
  const double w_scale = width / reach;
  std::vector<Eigen::Matrix<double, 6, 1>> rows(static_cast<std::size_t>(count));
  std::vector<double> heights(static_cast<std::size_t>(count)), weights(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) {
    const Eigen::Vector3d o = Eigen::Vector3d(offsets[3 * k], offsets[3 * k + 1], offsets[3 * k + 2]) / reach;
    const double u = o.dot(t1), v = o.dot(t2);
    rows[std::size_t(k)] << 1, u, v, u * u, u * v, v * v;
    heights[std::size_t(k)] = o.dot(n);
    const double r = heights[std::size_t(k)] / w_scale;
    weights[std::size_t(k)] = std::exp(-0.5 * r * r);
  }
  Eigen::Matrix<double, 6, 1> c = Eigen::Matrix<double, 6, 1>::Zero();
  for (int step = 0; step < kReweightSteps; ++step) {
    Eigen::Matrix<double, 6, 6> m = Eigen::Matrix<double, 6, 6>::Identity() * 1e-12;
    Eigen::Matrix<double, 6, 1> rhs = Eigen::Matrix<double, 6, 1>::Zero();
    for (int k = 0; k < count; ++k) {
      const auto& row = rows[std::size_t(k)];
      m.noalias() += weights[std::size_t(k)] * row * row.transpose();
      rhs.noalias() += weights[std::size_t(k)] * heights[std::size_t(k)] * row;
    }
    c = m.ldlt().solve(rhs);
    for (int k = 0; k < count; ++k) {
      const double r = (heights[std::size_t(k)] - rows[std::size_t(k)].dot(c)) / w_scale;
      weights[std::size_t(k)] = std::exp(-0.5 * r * r);
    }
  }
  const double slope = std::hypot(c(1), c(2));
  return std::isfinite(slope) ? std::atan(slope) : 0.0;
}

}  // namespace

SurfaceJudge::SurfaceJudge(const SpatialIndex& index, std::size_t samples, int neighbours, double width,
                           std::size_t among)
    : width_(width) {
  const std::vector<double>& centred = index.positions();
  const std::size_t points = centred.size() / 3, count = std::min(among, points);
  neighbours_ = int(std::min<std::size_t>(std::size_t(std::max(neighbours, 0)), points));
  samples = std::min(samples, count);
  if (samples == 0 || neighbours_ < kMinNeighbours || !(width > 0)) return;
  ids_.resize(samples);
  offsets_.resize(samples * std::size_t(neighbours_) * 3);
  const std::size_t k = std::size_t(neighbours_);
#pragma omp parallel
  {
    std::vector<std::size_t> ids(k);
    std::vector<double> distances(k);
#pragma omp for schedule(dynamic, 16)
    for (long long s = 0; s < static_cast<long long>(samples); ++s) {
      const std::size_t self = std::size_t(s) * count / samples;
      ids_[std::size_t(s)] = self;
      index.nearest_of_point(self, k, ids.data(), distances.data());
      double* out = &offsets_[std::size_t(s) * k * 3];
      for (std::size_t j = 0; j < k; ++j) {
        for (int axis = 0; axis < 3; ++axis) out[3 * j + axis] = centred[ids[j] * 3 + axis] - centred[self * 3 + axis];
      }
    }
  }
}

double SurfaceJudge::sum_squared(const double* normals_xyz) const {
  double sum = 0;
  const std::size_t k = std::size_t(neighbours_);
#pragma omp parallel for reduction(+ : sum) schedule(dynamic, 16)
  for (long long s = 0; s < static_cast<long long>(ids_.size()); ++s) {
    const std::size_t i = ids_[std::size_t(s)];
    const Eigen::Vector3d n(normals_xyz[3 * i], normals_xyz[3 * i + 1], normals_xyz[3 * i + 2]);
    const double a = error_in_frame(&offsets_[std::size_t(s) * k * 3], neighbours_, n, width_);
    sum += a * a;
  }
  return sum;
}

double SurfaceJudge::rms_deg(const double* normals_xyz) const {
  if (empty()) return 0;
  return std::sqrt(sum_squared(normals_xyz) / double(ids_.size())) * 180 / geometry::kPi;
}

}  // namespace pnf::detail
