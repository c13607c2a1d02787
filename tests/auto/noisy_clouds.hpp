// Clouds with known noise for the tests of pnf::estimate_data and pnf::choose_filter_params
// (auto_params_test.cpp, choose_filter_params_test.cpp).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "pnf/estimate_normals.hpp"
#include "test_clouds.hpp"

namespace pnf::test {

// The bars: spacing within 10%, position and angular noise within 25%.
constexpr double kSpacingTolerance = 0.10;
constexpr double kNoiseTolerance = 0.25;

// A plane z = 0 sampled uniformly at random: side `side` with `points` samples, so the spacing
// (square root of the area per point) is side / sqrt(points). Positions get Gaussian noise of
// `noise` spacings along z; normals +z, tilted by jitter_normal of `degrees`.
struct Noisy {
  PointCloud cloud;
  std::vector<Vec3> truth;
  double spacing = 0;
};

inline Noisy random_plane(int points, double noise, double degrees, unsigned seed) {
  std::mt19937 rng(seed);
  const double side = 10.0;
  std::uniform_real_distribution<double> u(0, side);
  Noisy n;
  n.spacing = side / std::sqrt(double(points));
  std::normal_distribution<double> g(0, noise * n.spacing);
  for (int i = 0; i < points; ++i) {
    n.cloud.positions.push_back({u(rng), u(rng), noise > 0 ? g(rng) : 0.0});
    n.truth.push_back({0, 0, 1});
    n.cloud.normals.push_back(degrees > 0 ? jitter_normal({0, 0, 1}, degrees, rng) : Vec3{0, 0, 1});
  }
  return n;
}

// A sphere of radius 5 with `points` random samples, noise along the radius and tilted normals.
inline Noisy noisy_sphere(int points, double noise, double degrees, unsigned seed) {
  constexpr double kRadius = 5.0;
  Noisy n;
  const PointCloud clean = sphere(points, kRadius, seed);
  n.spacing = std::sqrt(4 * kPi * kRadius * kRadius / points);
  std::mt19937 rng(seed + 1);
  std::normal_distribution<double> g(0, noise * n.spacing);
  for (std::size_t i = 0; i < clean.size(); ++i) {
    const Vec3& d = clean.normals[i];
    const double r = kRadius + (noise > 0 ? g(rng) : 0.0);
    n.cloud.positions.push_back({r * d[0], r * d[1], r * d[2]});
    n.truth.push_back(d);
    n.cloud.normals.push_back(degrees > 0 ? jitter_normal(d, degrees, rng) : d);
  }
  return n;
}

// The same cloud with PCA normals over k neighbours of its positions.
inline Noisy with_pca_normals(Noisy n, int k) {
  EstimateParams params;
  params.k = k;
  n.cloud.normals = estimate_normals(n.cloud.positions, params);
  return n;
}

inline double rms_angle(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += angle_deg(a[i], b[i]) * angle_deg(a[i], b[i]);
  return std::sqrt(sum / double(a.size()));
}

inline void expect_relative(double got, double want, double tolerance, const std::string& what) {
  EXPECT_NEAR(got / want, 1.0, tolerance) << what << ": estimated " << got << ", true " << want;
}

}  // namespace pnf::test
