// The small vector geometry of pnf's C++ side (the library, the host code, the tools and the
// benchmarks), written once: pi, dot, cross, length, unit vectors, tangent bases, and the angle between two directions.
// The OpenCL kernels have their own (kernels/pnf_common.h), in the language they share with the
// reference.
#pragma once

#include <cmath>

#include "pnf/point_cloud.hpp"

namespace pnf::geometry {

constexpr double kPi = 3.14159265358979323846;

inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// Euclidean length.
inline double norm(const Vec3& v) { return std::sqrt(dot(v, v)); }

// v / |v|, for a non-zero v.
inline Vec3 normalized(const Vec3& v) {
  const double len = norm(v);
  return {v[0] / len, v[1] / len, v[2] / len};
}

// Two unit vectors that make an orthonormal basis of the plane normal to the unit vector n.
// The helper axis is at least 37 degrees from n, so the first cross product never nears zero.
inline void tangent_basis(const Vec3& n, Vec3& t1, Vec3& t2) {
  const Vec3 helper = std::fabs(n[0]) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  t1 = normalized(cross(n, helper));
  t2 = cross(n, t1);
}

// The angle between two non-zero directions, in radians, 0 to pi. atan2(|a x b|, a . b) rather
// than acos(a . b / |a| |b|): acos cannot resolve angles below about 1e-6 degrees (its slope is
// infinite at 1), atan2 is exact to rounding at every angle, and no normalisation is needed.
inline double angle_radians(const Vec3& a, const Vec3& b) { return std::atan2(norm(cross(a, b)), dot(a, b)); }

// The same in degrees, 0 to 180.
inline double angle_degrees(const Vec3& a, const Vec3& b) { return angle_radians(a, b) * 180.0 / kPi; }

}  // namespace pnf::geometry
