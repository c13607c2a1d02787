#include "pnf/synthetic_shapes.hpp"

#include <cmath>
#include <functional>
#include <random>

#include "geometry.hpp"
#include "pnf/error.hpp"

namespace pnf {
namespace {

using geometry::kPi;
constexpr double kWidth = 100, kWallHeight = 60, kRoofRise = 50;  // 45-degree roof: rise = half width
const Vec3 kOffset = {1000, 2000, 500};
// Jitter within the face, as a fraction of the spacing: irregular like a scan, never overlapping.
constexpr double kInPlaneJitter = 0.3;

Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3 scale(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3 unit(const Vec3& a) { return scale(a, 1 / std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])); }

// A planar face: origin + a u + b v for (a, b) in [0, a_max] x [0, b_max] where `inside` holds;
// the outward normal is u x v.
struct Face {
  Vec3 origin, u, v;
  double a_max, b_max;
  std::function<bool(double, double)> inside;
};

std::vector<Face> house_faces() {
  const double s = std::sqrt(0.5), slope = kRoofRise / s;  // slope length along the roof
  const double eave = kWallHeight, ridge = kWallHeight + kRoofRise, half = kWidth / 2;
  auto all = [](double, double) { return true; };
  return {
      {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, kWidth, kWidth, all},     // floor, -z
      {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}, eave, kWidth, all},       // wall x = 0, -x
      {{kWidth, 0, 0}, {0, 1, 0}, {0, 0, 1}, kWidth, eave, all},  // wall x = w, +x
      {{0, 0, 0},
       {1, 0, 0},
       {0, 0, 1},
       kWidth,
       ridge,  // gable y = 0, -y
       [=](double x, double z) { return z <= ridge - std::fabs(x - half); }},
      {{0, kWidth, 0},
       {0, 0, 1},
       {1, 0, 0},
       ridge,
       kWidth,  // gable y = w, +y
       [=](double z, double x) { return z <= ridge - std::fabs(x - half); }},
      {{0, 0, eave}, {s, 0, s}, {0, 1, 0}, slope, kWidth, all},       // roof, (-1, 0, 1)
      {{half, 0, ridge}, {s, 0, -s}, {0, 1, 0}, slope, kWidth, all},  // roof, (1, 0, 1)
  };
}

}  // namespace

SyntheticCloud make_scanned_house(std::size_t points, const ScanNoise& noise) {
  if (points < 100)
    throw Error(ErrorCode::invalid_argument,
                "make_scanned_house needs at least 100 points, not " + std::to_string(points));
  if (!(noise.position >= 0) || !(noise.normal_degrees >= 0) || !std::isfinite(noise.position) ||
      !std::isfinite(noise.normal_degrees)) {
    throw Error(ErrorCode::invalid_argument, "scan noise must be finite and >= 0");
  }
  const std::vector<Face> faces = house_faces();
  // Total area of the closed house: floor, two walls, two gables (rectangle + triangle), roof.
  const double area = kWidth * kWidth + 2 * kWidth * kWallHeight + 2 * (kWidth * kWallHeight + kWidth * kRoofRise / 2) +
                      2 * kWidth * kRoofRise / std::sqrt(0.5);
  SyntheticCloud out;
  out.spacing = std::sqrt(area / double(points));
  const double h = out.spacing;
  std::mt19937_64 rng(noise.seed);
  std::uniform_real_distribution<double> jitter(-kInPlaneJitter * h, kInPlaneJitter * h);
  std::normal_distribution<double> offset(0, noise.position * h);
  std::normal_distribution<double> tilt(0, std::tan(noise.normal_degrees * kPi / 180));
  for (const Face& f : faces) {
    const Vec3 n = unit(cross(f.u, f.v));
    for (double a0 = 0.5 * h; a0 < f.a_max; a0 += h) {
      for (double b0 = 0.5 * h; b0 < f.b_max; b0 += h) {
        double a = std::min(std::max(a0 + jitter(rng), 0.0), f.a_max);
        double b = std::min(std::max(b0 + jitter(rng), 0.0), f.b_max);
        if (!f.inside(a, b)) continue;
        Vec3 p = add(add(f.origin, scale(f.u, a)), scale(f.v, b));
        p = add(add(p, scale(n, offset(rng))), kOffset);
        Vec3 noisy = unit(add(add(n, scale(f.u, tilt(rng))), scale(f.v, tilt(rng))));
        out.cloud.positions.push_back(p);
        out.cloud.normals.push_back(noisy);
        out.true_normals.push_back(n);
      }
    }
  }
  return out;
}

}  // namespace pnf
