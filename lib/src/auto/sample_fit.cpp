#include "sample_fit.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "geometry.hpp"
#include "quadric_moments.hpp"
#include "sample_neighbourhoods.hpp"

namespace pnf::detail {
namespace {

using geometry::angle_degrees;
using geometry::kPi;

// The correlation of the input normals' errors is taken between each sample and the points within
// this many spacings of it: PCA normals from 16 neighbours (a radius of about 2.3 spacings) share
// little there, from 64 (4.5 spacings) most of their neighbours.
constexpr double kCorrelationReachSpacings = 2.5;

// The positions' own normal at a sample, to which the input normal's error is compared for the
// coupling: PCA over this many nearest points (the sample included), the smallest common PCA
// neighbourhood, whose error is mostly the noise of the positions near the sample.
constexpr int kCouplingNeighbours = 16;

// A neighbour whose input normal turns from the sample's by more than this (the cosine of 154
// degrees) lies on another sheet: the far wall of a thin part, which faces the other way. Fitted
// with the sample's own sheet, its gap reads as position noise (the cup sampled at 10k points:
// the nearest point of its other wall a median 7 nearest-neighbour distances away, inside the
// smallest fits, read as 6.1 spacings of noise on clean positions; docs/auto.md, "Sparse
// clouds"). A single sheet turns its normals that far only at a crease sharper than 26 degrees,
// and noise only where two normals each err by some 77 degrees: at 120 degrees the noisiest PCA
// normals lost points of their own sheet (the casting at 6k points and 0.6% noise).
constexpr double kOtherSheetCos = -0.9;

// Whether the normals `a` and `b` (any length) face away from each other: another sheet.
bool face_away(const Vec3& a, const Vec3& b) {
  return geometry::dot(a, b) < kOtherSheetCos * geometry::norm(a) * geometry::norm(b);
}

// Which of the neighbourhood `ids` lie on the sample's own sheet: all unless `by_sheet`.
std::vector<char> on_own_sheet(const CloudView& cloud, std::size_t self, const std::size_t* ids, int count,
                               bool by_sheet) {
  std::vector<char> own(static_cast<std::size_t>(count), 1);
  if (!by_sheet) return own;
  const Vec3 mine = cloud.normals.at(self);
  for (int k = 0; k < count; ++k) own[std::size_t(k)] = !face_away(mine, cloud.normals.at(ids[k]));
  return own;
}

// The unit normal of the plane through the kCouplingNeighbours nearest of `offsets` on the
// sample's sheet (PCA), on the side of `side`; zero when fewer points are there or they span no
// plane.
Eigen::Vector3d nearest_points_normal(const std::vector<Eigen::Vector3d>& offsets, const double* squared_distances,
                                      const std::vector<char>& own_sheet, const Eigen::Vector3d& side) {
  std::vector<int> order;
  for (int k = 0; k < int(offsets.size()); ++k) {
    if (own_sheet[std::size_t(k)]) order.push_back(k);
  }
  if (int(order.size()) < kCouplingNeighbours) return Eigen::Vector3d::Zero();
  std::nth_element(order.begin(), order.begin() + (kCouplingNeighbours - 1), order.end(),
                   [&](int a, int b) { return squared_distances[a] < squared_distances[b]; });
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int k = 0; k < kCouplingNeighbours; ++k) centroid += offsets[std::size_t(order[std::size_t(k)])];
  centroid /= double(kCouplingNeighbours);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (int k = 0; k < kCouplingNeighbours; ++k) {
    const Eigen::Vector3d o = offsets[std::size_t(order[std::size_t(k)])] - centroid;
    covariance += o * o.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  if (!(eigen.eigenvalues()(1) > 0)) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d normal = eigen.eigenvectors().col(0);
  return normal.dot(side) < 0 ? Eigen::Vector3d(-normal) : normal;
}

}  // namespace

bool normals_oriented(const CloudView& cloud, const SampleNeighbourhoods& nearest) {
  if (!cloud.has_normals()) return false;
  std::size_t facing_away = 0, pairs = 0;
  for (std::size_t s = 0; s < nearest.samples(); ++s) {
    const std::size_t self = nearest.selves[s];
    const std::size_t* ids = nearest.ids_of(s);
    for (int k = 0; k < nearest.neighbours; ++k) {
      if (ids[k] == self) continue;
      facing_away += face_away(cloud.normals.at(self), cloud.normals.at(ids[k]));
      ++pairs;
      break;
    }
  }
  return 4 * facing_away <= pairs;
}

SampleFit fit_sample(const std::vector<double>& centred, const CloudView& cloud, std::size_t self,
                     const std::size_t* ids, const double* squared_distances, int count, bool by_sheet) {
  SampleFit fit;
  const Eigen::Vector3d origin(centred[self * 3], centred[self * 3 + 1], centred[self * 3 + 2]);
  // The surface is fitted to the sample's own sheet; the density counts every point.
  const std::vector<char> own_sheet = on_own_sheet(cloud, self, ids, count, by_sheet);
  std::vector<Eigen::Vector3d> offsets(static_cast<std::size_t>(count));
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double farthest_squared = 0;
  int on_sheet = 0;
  for (int k = 0; k < count; ++k) {
    const std::size_t id = ids[k];
    offsets[std::size_t(k)] = Eigen::Vector3d(centred[id * 3], centred[id * 3 + 1], centred[id * 3 + 2]) - origin;
    farthest_squared = std::max(farthest_squared, squared_distances[k]);  // FLANN's L2 is squared
    if (!own_sheet[std::size_t(k)]) continue;
    centroid += offsets[std::size_t(k)];
    ++on_sheet;
  }
  centroid /= double(on_sheet);  // the sample itself is on its sheet
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (int k = 0; k < count; ++k) {
    if (!own_sheet[std::size_t(k)]) continue;
    const Eigen::Vector3d o = offsets[std::size_t(k)] - centroid;
    covariance += o * o.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  const Eigen::Vector3d normal = eigen.eigenvectors().col(0);
  const Eigen::Vector3d t1 = eigen.eigenvectors().col(2);
  const Eigen::Vector3d t2 = normal.cross(t1);
  const double rho = kCylinderFraction * std::sqrt(farthest_squared);
  if (!(rho > 0) || !(eigen.eigenvalues()(1) > 0)) return fit;

  // Least squares in coordinates relative to the sample, scaled by rho (well conditioned at any
  // model scale), over the points within rho of the normal's axis, each weighed alike.
  thread_local std::vector<double> us, vs, heights, ones;  // one fit at a time per thread
  us.clear(), vs.clear(), heights.clear();
  int in_cylinder = 0;
  for (int k = 0; k < count; ++k) {
    const Eigen::Vector3d& o = offsets[std::size_t(k)];
    const double u = o.dot(t1) / rho, v = o.dot(t2) / rho;
    if (u * u + v * v > 1.0) continue;
    ++in_cylinder;
    if (own_sheet[std::size_t(k)]) us.push_back(u), vs.push_back(v), heights.push_back(o.dot(normal) / rho);
  }
  const int fitted = int(us.size());
  if (fitted < kMinFitPoints) return fit;
  ones.assign(us.size(), 1.0);
  double sums[kQuadricMoments];
  quadric_moment_sums(ones.data(), us.data(), vs.data(), heights.data(), us.size(), sums);
  const QuadricVector c = quadric_normal_matrix(sums).ldlt().solve(quadric_right_side(sums));
  double rss = 0;
  for (std::size_t k = 0; k < us.size(); ++k) {
    const double r = heights[k] - quadric_height(c, us[k], vs[k]);
    rss += r * r;
  }
  fit.ok = std::isfinite(rss);
  fit.radius = rho;
  fit.residual = rho * std::sqrt(rss / double(fitted - 6));
  fit.area_spacing = std::sqrt(kPi * rho * rho / double(in_cylinder));
  {
    // Hessian of the height field in model units: the fit is in units of rho.
    const double a = 2 * c(3) / rho, b = c(4) / rho, d = 2 * c(5) / rho;
    fit.curvature = std::abs(0.5 * (a + d)) + std::sqrt(0.25 * (a - d) * (a - d) + b * b);
  }
  if (cloud.has_normals()) {
    // The quadric's unit normal at (u, v) (in units of rho), and the input normal of point `id`
    // as a unit vector on the same side, or zero when it has no direction.
    auto surface_at = [&](double u, double v) {
      return (normal - (c(1) + 2 * c(3) * u + c(4) * v) * t1 - (c(2) + c(4) * u + 2 * c(5) * v) * t2).normalized();
    };
    auto input_towards = [&](std::size_t id, const Eigen::Vector3d& side) -> Eigen::Vector3d {
      const Vec3 n = cloud.normals.at(id);
      const Eigen::Vector3d input(n[0], n[1], n[2]);
      const double length = input.norm();
      if (!(length > 0) || !std::isfinite(length)) return Eigen::Vector3d::Zero();
      return input.dot(side) < 0 ? Eigen::Vector3d(-input / length) : Eigen::Vector3d(input / length);
    };
    const Eigen::Vector3d surface = surface_at(0, 0);
    const Eigen::Vector3d input = input_towards(self, surface);
    if (input.squaredNorm() > 0) {
      fit.angle_deg = angle_degrees({surface.x(), surface.y(), surface.z()}, {input.x(), input.y(), input.z()});
      const Eigen::Vector3d error = input - surface;
      const Eigen::Vector3d from_positions = nearest_points_normal(offsets, squared_distances, own_sheet, surface);
      if (from_positions.squaredNorm() > 0) {
        const Eigen::Vector3d positions_error = from_positions - surface;
        fit.coupling_dot = error.dot(positions_error);
        fit.coupling_input_squared = error.squaredNorm();
        fit.coupling_positions_squared = positions_error.squaredNorm();
      }
      const double reach = kCorrelationReachSpacings * fit.area_spacing;
      Eigen::Vector3d local_error = error;
      int local_count = 1;
      for (int k = 0; k < count; ++k) {
        if (ids[k] == self || !own_sheet[std::size_t(k)]) continue;
        const Eigen::Vector3d& o = offsets[std::size_t(k)];
        const double u = o.dot(t1), v = o.dot(t2);
        if (u * u + v * v > reach * reach) continue;
        const Eigen::Vector3d there = surface_at(u / rho, v / rho);
        const Eigen::Vector3d other = input_towards(ids[k], there);
        if (other.squaredNorm() == 0) continue;
        fit.error_dot += error.dot(other - there);
        fit.error_magnitudes += error.norm() * (other - there).norm();
        local_error += other - there;
        ++local_count;
      }
      // |a - b| = 2 sin(angle / 2) for unit vectors a, b.
      const double chord = std::min(2.0, local_error.norm() / double(local_count));
      fit.local_angle_deg = 2 * std::asin(0.5 * chord) * 180 / kPi;
    }
  }
  return fit;
}

}  // namespace pnf::detail
