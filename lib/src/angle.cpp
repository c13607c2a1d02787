#include "pnf/angle.hpp"

#include "geometry.hpp"

namespace pnf {

double angle_degrees(const Vec3& a, const Vec3& b) { return geometry::angle_degrees(a, b); }

}  // namespace pnf
