#include "cloud_checks.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "pnf/error.hpp"

namespace pnf::detail {
namespace {

bool finite(const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

double length(const Vec3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

[[noreturn]] void fail(const std::string& what) { throw Error(ErrorCode::invalid_input, what); }

}  // namespace

void check_cloud(const PointCloud& cloud) {
  const std::size_t n = cloud.size();
  if (n >= std::numeric_limits<std::uint32_t>::max()) {
    fail("the cloud has " + std::to_string(n) + " points; pnf handles at most 4294967294");
  }
  if (n > 0 && cloud.normals.empty()) {
    fail("the cloud has no normals; estimate them first (pnf estimate, or pnf::estimate_normals)");
  }
  if (cloud.normals.size() != n) {
    fail("the cloud has " + std::to_string(n) + " positions but " + std::to_string(cloud.normals.size()) + " normals");
  }
  if (!cloud.radii.empty() && cloud.radii.size() != n) {
    fail("the cloud has " + std::to_string(n) + " positions but " + std::to_string(cloud.radii.size()) + " radii");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!finite(cloud.positions[i])) fail("vertex " + std::to_string(i) + " has a NaN or infinite coordinate");
    if (!finite(cloud.normals[i])) fail("vertex " + std::to_string(i) + " has a NaN or infinite normal component");
    // A normal this short has no direction left to keep after normalisation.
    if (!(length(cloud.normals[i]) > std::numeric_limits<double>::min())) {
      fail("vertex " + std::to_string(i) + " has a zero-length normal");
    }
    if (!cloud.radii.empty() && !(std::isfinite(cloud.radii[i]) && cloud.radii[i] > 0)) {
      fail("vertex " + std::to_string(i) + " has radius " + std::to_string(cloud.radii[i]) +
           "; must be finite and > 0");
    }
  }
}

std::vector<Vec3> unit_normals(const std::vector<Vec3>& normals) {
  std::vector<Vec3> out(normals.size());
  for (std::size_t i = 0; i < normals.size(); ++i) {
    double len = length(normals[i]);
    out[i] = {normals[i][0] / len, normals[i][1] / len, normals[i][2] / len};
  }
  return out;
}

}  // namespace pnf::detail
