// The shapes and scores of the issue-14 tests (auto_params_creases_test and the others that include it):
// single creases with known true normals, the RMS line angle to the truth, and the fastest
// filter this machine has.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "pnf/estimate_normals.hpp"
#include "pnf/normal_filter.hpp"
#include "test_backends.hpp"
#include "test_clouds.hpp"

namespace pnf::test {

// Two unit squares meeting along the y axis at the dihedral angle `degrees` (180: one plane):
// a crease 1 long in an area of 2, sampled uniformly at random with `points` samples, so the
// spacing (square root of the area per point) is sqrt(2 / points). Gaussian position noise of
// `noise` spacings per axis.
struct Crease {
  PointCloud cloud;
  std::vector<Vec3> truth;
  double spacing = 0;
};

inline Crease make_crease(double degrees, int points, double noise, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u01(0, 1);
  const double t = degrees * kPi / 180;
  // Face b leaves the crease in direction (-cos t, 0, sin t), at the angle t to face a's (-1, 0, 0);
  // both normals point into the wedge between the faces.
  const Vec3 along_b = {-std::cos(t), 0, std::sin(t)};
  const Vec3 normal_b = {-std::sin(t), 0, -std::cos(t)};
  Crease c;
  c.spacing = std::sqrt(2.0 / points);
  std::normal_distribution<double> g(0, noise * c.spacing);
  for (int i = 0; i < points; ++i) {
    const double s = u01(rng), y = u01(rng);
    Vec3 p;
    if (u01(rng) < 0.5) {
      p = {-s, y, 0};
      c.truth.push_back({0, 0, 1});
    } else {
      p = {s * along_b[0], y, s * along_b[2]};
      c.truth.push_back(normal_b);
    }
    if (noise > 0) p = {p[0] + g(rng), p[1] + g(rng), p[2] + g(rng)};
    c.cloud.positions.push_back(p);
  }
  return c;
}

// RMS angle between the normals and the truth as lines (min(t, 180 - t)), degrees.
inline double rms_line_angle(const std::vector<Vec3>& normals, const std::vector<Vec3>& truth) {
  double sum = 0;
  for (std::size_t i = 0; i < normals.size(); ++i) {
    const double t = angle_deg(normals[i], truth[i]);
    sum += std::min(t, 180 - t) * std::min(t, 180 - t);
  }
  return std::sqrt(sum / double(normals.size()));
}

inline NormalFilter& fastest_filter() {
  std::string why;
  NormalFilter* f = opencl_filter(why);
  return f ? *f : *reference_filter();
}

// PCA normals over 16 points (the point and its 15 nearest, as `pnf estimate` counts k), turned
// to the true side (a sign only; the filter needs consistent signs, the score ignores them), as
// `pnf estimate` would give a scan.
inline std::vector<Vec3> pca16_normals(const std::vector<Vec3>& positions, const std::vector<Vec3>& truth) {
  EstimateParams params;
  params.k = 16;
  params.orientation = Orientation::outward;  // cheap; replaced by the true side below
  std::vector<Vec3> normals = estimate_normals(positions, params);
  for (std::size_t i = 0; i < normals.size(); ++i) {
    if (dot(normals[i], truth[i]) < 0) normals[i] = {-normals[i][0], -normals[i][1], -normals[i][2]};
  }
  return normals;
}

}  // namespace pnf::test
