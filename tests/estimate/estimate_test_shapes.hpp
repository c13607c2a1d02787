// The shapes, tolerances and checks of the estimate_normals tests (estimate_normals_test.cpp,
// estimate_normals_input_test.cpp): noisy samples of a plane, sphere, cube and torus with their
// analytic normals, agreement with them, and a brute-force PCA fit to compare against.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "expect_error.hpp"
#include "pnf/error.hpp"
#include "pnf/estimate_normals.hpp"

namespace pnf::test::estimate {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kDegreesPerRadian = 180.0 / kPi;

// Position noise, as a fraction of the shape's size (unit radius / half-width). About a tenth of
// the sample spacing used below, i.e. a mildly noisy scan; it tilts a 16-neighbour PCA plane by
// roughly noise / neighbourhood radius, about a degree.
inline constexpr double kNoise = 0.002;

// Angle bounds between an estimated and the true normal (degrees), each a margin over what the
// fixed-seed clouds below give with libstdc++ (in brackets), because another standard library
// draws different random numbers from the same seeds.
// Noise alone tilts a 16-neighbour plane by about kNoise / neighbourhood radius, ~1° [mean 0.75,
// max 2.7 on the plane].
inline constexpr double kPlaneMaxAngleDegrees = 5.0;
inline constexpr double kMeanAngleDegrees = 1.5;
// On a curved surface PCA returns the normal at the centroid of the neighbourhood, which random
// sampling puts off the point by a fraction of the neighbourhood radius; the error is curvature
// times that offset [sphere, curvature 1: mean 1.0, max 4.4].
inline constexpr double kSphereMaxAngleDegrees = 8.0;
// The torus tube has curvature 1/0.35, so the same effect is about three times larger [mean 2.1,
// max 8.5; noise-free sampling alone gives mean 1.9].
inline constexpr double kTorusMeanAngleDegrees = 3.0;
// Share of points whose orientation must agree with the true normal (the brief's 99%).
inline constexpr double kOrientedShare = 0.99;

inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

inline Vec3 normalised(const Vec3& v) {
  const double length = std::sqrt(dot(v, v));
  return {v[0] / length, v[1] / length, v[2] / length};
}

// Angle in degrees between two unit vectors, ignoring their sign (the PCA error alone). atan2 of
// |a × b| and |a · b| rather than acos, which cannot resolve angles below ~1e-6° near 1.
inline double line_angle_degrees(const Vec3& a, const Vec3& b) {
  const Vec3 cross = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  return std::atan2(std::sqrt(dot(cross, cross)), std::abs(dot(a, b))) * kDegreesPerRadian;
}

struct Sample {
  std::vector<Vec3> positions;
  std::vector<Vec3> true_normals;  // unit, outward (or +z for open sheets)
};

inline void add_point(Sample& sample, const Vec3& on_surface, const Vec3& normal, double noise) {
  sample.positions.push_back(
      {on_surface[0] + noise * normal[0], on_surface[1] + noise * normal[1], on_surface[2] + noise * normal[2]});
  sample.true_normals.push_back(normal);
}

// The plane z = 0.3 x + 0.2 y over [-1, 1]^2, with Gaussian noise along its normal.
inline Sample noisy_plane(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, kNoise);
  const Vec3 normal = normalised({-0.3, -0.2, 1.0});
  Sample sample;
  for (int i = 0; i < count; ++i) {
    const double x = coordinate(rng);
    const double y = coordinate(rng);
    add_point(sample, {x, y, 0.3 * x + 0.2 * y}, normal, noise(rng));
  }
  return sample;
}

// Uniform points on the sphere of radius `radius` about `centre`, with radial Gaussian noise.
inline Sample noisy_sphere(int count, unsigned seed, const Vec3& centre = {0.0, 0.0, 0.0}, double radius = 1.0) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, kNoise * radius);
  Sample sample;
  for (int i = 0; i < count; ++i) {
    const Vec3 normal = normalised({gaussian(rng), gaussian(rng), gaussian(rng)});
    add_point(sample, {centre[0] + radius * normal[0], centre[1] + radius * normal[1], centre[2] + radius * normal[2]},
              normal, noise(rng));
  }
  return sample;
}

// Uniform points on the surface of the cube [-1, 1]^3, with noise along the face normal.
inline Sample noisy_cube(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> face(0, 5);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, kNoise);
  Sample sample;
  for (int i = 0; i < count; ++i) {
    const int f = face(rng);
    const int axis = f / 2;
    const double side = (f % 2 == 0) ? 1.0 : -1.0;
    Vec3 point;
    Vec3 normal = {0.0, 0.0, 0.0};
    point[axis] = side;
    point[(axis + 1) % 3] = coordinate(rng);
    point[(axis + 2) % 3] = coordinate(rng);
    normal[axis] = side;
    add_point(sample, point, normal, noise(rng));
  }
  return sample;
}

// Uniform points on a torus about the z axis (tube centre radius 1, tube radius 0.35), by
// rejection on the area element (1 + 0.35 cos v), with noise along the normal.
inline Sample noisy_torus(int count, unsigned seed) {
  constexpr double kRing = 1.0;
  constexpr double kTube = 0.35;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * kPi);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, kNoise);
  Sample sample;
  while (static_cast<int>(sample.positions.size()) < count) {
    const double u = angle(rng);
    const double v = angle(rng);
    if (unit(rng) * (kRing + kTube) > kRing + kTube * std::cos(v)) continue;
    const Vec3 normal = {std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v)};
    const double ring = kRing + kTube * std::cos(v);
    add_point(sample, {ring * std::cos(u), ring * std::sin(u), kTube * std::sin(v)}, normal, noise(rng));
  }
  return sample;
}

struct Agreement {
  double oriented_share = 0.0;  // share of points with n · n_true > 0
  double max_angle_degrees = 0.0;
  double mean_angle_degrees = 0.0;
  std::size_t worst_index = 0;
};

inline Agreement compare(const std::vector<Vec3>& estimated, const std::vector<Vec3>& truth) {
  Agreement result;
  std::size_t oriented = 0;
  double angle_sum = 0.0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (dot(estimated[i], truth[i]) > 0.0) ++oriented;
    const double angle = line_angle_degrees(estimated[i], truth[i]);
    angle_sum += angle;
    if (angle > result.max_angle_degrees) {
      result.max_angle_degrees = angle;
      result.worst_index = i;
    }
  }
  result.oriented_share = static_cast<double>(oriented) / static_cast<double>(truth.size());
  result.mean_angle_degrees = angle_sum / static_cast<double>(truth.size());
  return result;
}

inline void expect_unit_normals(const std::vector<Vec3>& normals, std::size_t count) {
  // Eigen's eigenvectors and our division leave the length within a few ulps of 1.
  constexpr double kUnitTolerance = 1e-12;
  ASSERT_EQ(normals.size(), count);
  for (std::size_t i = 0; i < normals.size(); ++i) {
    const Vec3& n = normals[i];
    ASSERT_TRUE(std::isfinite(n[0]) && std::isfinite(n[1]) && std::isfinite(n[2])) << "point " << i;
    ASSERT_NEAR(std::sqrt(dot(n, n)), 1.0, kUnitTolerance) << "point " << i;
  }
}

inline EstimateParams params_with(Orientation orientation, int k = 16) {
  EstimateParams params;
  params.orientation = orientation;
  params.k = k;
  return params;
}

// The PCA fit of point i over its k nearest points (itself included), found by brute force:
// the eigenvalues of their covariance about the centroid, increasing, and the eigenvector of
// the smallest (unsigned).
struct BruteForceFit {
  Vec3 normal;
  std::array<double, 3> eigenvalues;
};

inline BruteForceFit brute_force_fit(const std::vector<Vec3>& positions, std::size_t i, int k) {
  std::vector<std::pair<double, std::size_t>> by_distance;
  for (std::size_t j = 0; j < positions.size(); ++j) {
    const Vec3 d = {positions[j][0] - positions[i][0], positions[j][1] - positions[i][1],
                    positions[j][2] - positions[i][2]};
    by_distance.push_back({dot(d, d), j});
  }
  std::sort(by_distance.begin(), by_distance.end());
  const std::size_t count = std::min(std::size_t(k), positions.size());
  // Offsets from point i, as the library takes them.
  std::vector<Eigen::Vector3d> offsets;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (std::size_t s = 0; s < count; ++s) {
    const Vec3& q = positions[by_distance[s].second];
    offsets.emplace_back(q[0] - positions[i][0], q[1] - positions[i][1], q[2] - positions[i][2]);
    centroid += offsets.back();
  }
  centroid /= double(count);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& o : offsets) covariance += (o - centroid) * (o - centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  const Eigen::Vector3d n = solver.eigenvectors().col(0).normalized();
  const Eigen::Vector3d values = solver.eigenvalues();
  return {{n[0], n[1], n[2]}, {values[0], values[1], values[2]}};
}

}  // namespace pnf::test::estimate
