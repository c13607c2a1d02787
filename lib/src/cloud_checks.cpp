#include "cloud_checks.hpp"

#include <cmath>
#include <limits>

#include "pnf/error.hpp"

namespace pnf::detail {
namespace {

bool finite(const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

double length(const Vec3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

}  // namespace

void check_cloud(const CloudView& cloud, const CloudRequirements& requirements) {
  const std::string prefix = requirements.caller.empty() ? "" : requirements.caller + ": ";
  auto fail = [&](const std::string& what) { throw Error(ErrorCode::invalid_input, prefix + what); };
  const std::size_t n = cloud.size();
  if (n < requirements.min_points) {
    fail("need at least " + std::to_string(requirements.min_points) + " points, got " + std::to_string(n));
  }
  if (n > requirements.max_points) {
    fail("the cloud has " + std::to_string(n) + " points; at most " + std::to_string(requirements.max_points) +
         " are supported");
  }
  if (n > 0 && cloud.positions.data == nullptr) fail("the positions view has no data");
  if (requirements.needs_normals && n > 0 && !cloud.has_normals()) {
    fail("the cloud has no normals; estimate them first (pnf estimate, or pnf::estimate_normals)");
  }
  if (cloud.has_normals() && cloud.normals.count != n) {
    fail("the cloud has " + std::to_string(n) + " positions but " + std::to_string(cloud.normals.count) + " normals");
  }
  if (cloud.has_radii() && cloud.radii.count != n) {
    fail("the cloud has " + std::to_string(n) + " positions but " + std::to_string(cloud.radii.count) + " radii");
  }
  const bool normals = cloud.has_normals() && requirements.checks_normals;
  for (std::size_t i = 0; i < n; ++i) {
    if (!finite(cloud.positions.at(i))) fail("vertex " + std::to_string(i) + " has a NaN or infinite coordinate");
    if (normals) {
      const Vec3 normal = cloud.normals.at(i);
      if (!finite(normal)) fail("vertex " + std::to_string(i) + " has a NaN or infinite normal component");
      // A normal this short has no direction left to keep after normalisation; one whose
      // squared length overflows (components from about 1e154) would normalise to 0 or NaN.
      const double normal_length = length(normal);
      if (!(normal_length > std::numeric_limits<double>::min())) {
        fail("vertex " + std::to_string(i) + " has a zero-length normal" +
             (normal == Vec3{0, 0, 0} ? "" : " (its components, under about 1e-154, square to 0 in double)"));
      }
      if (!std::isfinite(normal_length)) {
        fail("vertex " + std::to_string(i) +
             " has a normal too long to normalise in double (components from about 1e154); scale it");
      }
    }
    if (cloud.has_radii()) {
      const double radius = cloud.radii.get(i);
      if (!valid_radius(radius)) {
        fail("vertex " + std::to_string(i) + " has radius " + std::to_string(radius) + "; must be finite and > 0");
      }
    }
  }
}

std::vector<double> unit_normals(const Vec3ArrayView& normals) {
  std::vector<double> out(3 * normals.count);
  for (std::size_t i = 0; i < normals.count; ++i) {
    const Vec3 n = normals.at(i);
    const double len = length(n);
    for (int c = 0; c < 3; ++c) out[3 * i + c] = n[c] / len;
  }
  return out;
}

}  // namespace pnf::detail
