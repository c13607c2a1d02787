// pnf::angle_degrees (pnf/angle.hpp), against angles known in closed form.
#include "pnf/angle.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using pnf::angle_degrees;
using pnf::Vec3;

constexpr double kPi = 3.14159265358979323846;

TEST(AngleDegrees, KnownAngles) {
  EXPECT_DOUBLE_EQ(angle_degrees({1, 0, 0}, {0, 1, 0}), 90.0);
  EXPECT_DOUBLE_EQ(angle_degrees({1, 0, 0}, {-1, 0, 0}), 180.0);
  EXPECT_NEAR(angle_degrees({1, 0, 0}, {0.5, std::sqrt(3.0) / 2, 0}), 60.0, 1e-12);
  // Lengths do not matter.
  EXPECT_NEAR(angle_degrees({3, 0, 0}, {0, 0.25, 0.25}), 90.0, 1e-12);
  EXPECT_NEAR(angle_degrees({2, 2, 0}, {0, 5, 0}), 45.0, 1e-12);
  EXPECT_EQ(angle_degrees({0, 0, 0}, {0, 0, 1}), 0.0);
}

TEST(AngleDegrees, ExactNearZero) {
  // A tilt of 1e-9 rad: acos of the dot product (1 - 5e-19, which rounds to 1) would say 0.
  const double t = 1e-9;
  const Vec3 a{0, 0, 1}, b{std::sin(t), 0, std::cos(t)};
  EXPECT_NEAR(angle_degrees(a, b), t * 180 / kPi, 1e-12 * t * 180 / kPi);
  EXPECT_EQ(angle_degrees(a, a), 0.0);
}

}  // namespace
