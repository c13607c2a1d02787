// Synthetic clouds with known normals, and angle measures, shared by the tests.
#pragma once

#include <cmath>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "pnf/point_cloud.hpp"

namespace pnf::test {

constexpr double kPi = 3.14159265358979323846;

inline double norm(const Vec3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 normalized(const Vec3& v) {
  double l = norm(v);
  return {v[0] / l, v[1] / l, v[2] / l};
}

// Rows x y z of `points`: N by 3, as the spatial index and the judge take them.
inline std::vector<double> xyz_rows(const std::vector<Vec3>& points) {
  std::vector<double> out;
  for (const Vec3& p : points) out.insert(out.end(), p.begin(), p.end());
  return out;
}

// Angle between two directions in degrees, robust near 0 (atan2 of cross and dot).
inline double angle_deg(const Vec3& a, const Vec3& b) {
  Vec3 c = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  return std::atan2(norm(c), dot(a, b)) * 180.0 / kPi;
}

inline double mean_angle_deg(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += angle_deg(a[i], b[i]);
  return sum / double(a.size());
}

// Rotates `n` by a random angle of about `degrees` (normal distribution of that scale on each
// tangent axis) around a random tangent direction.
inline Vec3 jitter_normal(const Vec3& n, double degrees, std::mt19937& rng) {
  std::normal_distribution<double> gauss(0.0, std::tan(degrees * kPi / 180.0));
  Vec3 helper = std::fabs(n[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  Vec3 t1 = normalized(
      {n[1] * helper[2] - n[2] * helper[1], n[2] * helper[0] - n[0] * helper[2], n[0] * helper[1] - n[1] * helper[0]});
  Vec3 t2 = {n[1] * t1[2] - n[2] * t1[1], n[2] * t1[0] - n[0] * t1[2], n[0] * t1[1] - n[1] * t1[0]};
  double a = gauss(rng), b = gauss(rng);
  return normalized({n[0] + a * t1[0] + b * t2[0], n[1] + a * t1[1] + b * t2[1], n[2] + a * t1[2] + b * t2[2]});
}

// A square grid of side `cells` with spacing `h` in the z = 0 plane, positions jittered in x and
// y by up to `jitter` * h, normals +z.
inline PointCloud jittered_grid(int cells, double h, double jitter, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-jitter * h, jitter * h);
  PointCloud c;
  for (int i = 0; i < cells; ++i) {
    for (int j = 0; j < cells; ++j) {
      c.positions.push_back({i * h + u(rng), j * h + u(rng), 0.0});
      c.normals.push_back({0, 0, 1});
    }
  }
  return c;
}

// Ripples of wavelength 0.4 on a jittered grid of spacing 0.01, with their true normals.
inline PointCloud rippled_grid() {
  PointCloud ripples = jittered_grid(100, 0.01, 0.3, 7);
  const double a = 0.01, k = 2 * kPi / 0.4;
  for (std::size_t i = 0; i < ripples.size(); ++i) {
    Vec3& p = ripples.positions[i];
    p[2] = a * std::sin(k * p[0]) * std::sin(k * p[1]);
    ripples.normals[i] = normalized(
        {-a * k * std::cos(k * p[0]) * std::sin(k * p[1]), -a * k * std::sin(k * p[0]) * std::cos(k * p[1]), 1});
  }
  return ripples;
}

// A 90-degree ridge along the y axis, z = -|x|: the faces z = x (x < 0) and z = -x (x >= 0) with
// upward normals (-1, 0, 1)/sqrt2 and (1, 0, 1)/sqrt2. Points on a grid of spacing h in (u, y),
// u the arc length across the edge, jittered within the surface by up to `jitter` * h.
inline PointCloud wedge(int half_cells, int length_cells, double h, double jitter, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u01(-jitter * h, jitter * h);
  PointCloud c;
  const double s = std::sqrt(0.5);
  for (int i = -half_cells; i <= half_cells; ++i) {
    for (int j = 0; j < length_cells; ++j) {
      double u = (i + 0.5) * h + u01(rng);  // +0.5: no point sits exactly on the edge
      double y = j * h + u01(rng);
      if (u < 0) {
        c.positions.push_back({u * s, y, u * s});  // z = x
        c.normals.push_back({-s, 0, s});
      } else {
        c.positions.push_back({u * s, y, -u * s});  // z = -x
        c.normals.push_back({s, 0, s});
      }
    }
  }
  return c;
}

// Random points on a sphere with outward normals.
inline PointCloud sphere(int points, double radius, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0, 1);
  PointCloud c;
  for (int i = 0; i < points; ++i) {
    Vec3 d = normalized({g(rng), g(rng), g(rng)});
    c.positions.push_back({radius * d[0], radius * d[1], radius * d[2]});
    c.normals.push_back(d);
  }
  return c;
}

// sphere(points, radius, seed) with each normal tilted at random by jitter_normal(n, degrees)
// (its own generator, seeded seed + 1).
inline PointCloud jittered_sphere(int points, double radius, unsigned seed, double degrees) {
  PointCloud c = sphere(points, radius, seed);
  std::mt19937 rng(seed + 1);
  for (Vec3& n : c.normals) n = jitter_normal(n, degrees, rng);
  return c;
}

// The folder of the team's shared test models, or "" when it is absent.
inline std::string shared_data_dir() {
  if (const char* env = std::getenv("PNF_SHARED_DATA")) return env;
#ifdef PNF_SHARED_DATA_DIR
  return PNF_SHARED_DATA_DIR;
#else
  return "";
#endif
}

}  // namespace pnf::test
