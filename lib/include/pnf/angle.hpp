// pnf::angle_degrees — the angle between two normals, as pnf measures it everywhere (`pnf
// compare`, the demo's report, the evaluations).
#pragma once

#include "pnf/point_cloud.hpp"

namespace pnf {

// The angle between a and b in degrees, 0 to 180 (oriented: opposite vectors are 180 apart).
// Computed as atan2(|a x b|, a . b), exact near 0 where acos of the dot product is not; a and b
// need not be unit length, and a zero vector gives 0.
double angle_degrees(const Vec3& a, const Vec3& b);

}  // namespace pnf
