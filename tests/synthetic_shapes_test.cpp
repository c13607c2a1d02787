#include "pnf/synthetic_shapes.hpp"

#include <gtest/gtest.h>

#include "test_clouds.hpp"

namespace {

using namespace pnf::test;

TEST(SyntheticShapes, NoiselessHouseLiesOnItsFacesWithOutwardNormals) {
  pnf::SyntheticCloud house = pnf::make_scanned_house(20000, pnf::ScanNoise{0, 0, 3});
  ASSERT_NEAR(double(house.cloud.size()), 20000, 1000);
  const pnf::Vec3 centre = {1050, 2050, 540};  // inside the convex house
  const pnf::Vec3 offset = {1000, 2000, 500};
  for (std::size_t i = 0; i < house.cloud.size(); ++i) {
    const pnf::Vec3& p = house.cloud.positions[i];
    const pnf::Vec3& n = house.true_normals[i];
    EXPECT_EQ(house.cloud.normals[i], n) << "no normal noise asked for";
    EXPECT_NEAR(norm(n), 1, 1e-12);
    EXPECT_GT(dot(n, {p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]}), 0) << "inward normal at " << i;
    // Every sample satisfies its face's plane equation n.(p - offset) = d for one of the 7 faces.
    const double s = std::sqrt(0.5);
    pnf::Vec3 q = {p[0] - offset[0], p[1] - offset[1], p[2] - offset[2]};
    double d = dot(n, q);
    double expected = n[2] == -1   ? 0
                      : n[0] == -1 ? 0
                      : n[0] == 1  ? 100
                      : n[1] == -1 ? 0
                      : n[1] == 1  ? 100
                      : n[0] < 0   ? 60 * s
                                   : 110 * s + 50 * s;
    EXPECT_NEAR(d, expected, 1e-9) << "sample " << i << " is off its face";
  }
}

TEST(SyntheticShapes, NoiseHasTheRequestedScale) {
  pnf::SyntheticCloud house = pnf::make_scanned_house(20000, pnf::ScanNoise{0.1, 15, 4});
  double mean_angle = mean_angle_deg(house.cloud.normals, house.true_normals);
  // Two independent tangent tilts of std tan(15 deg): the angle is Rayleigh, mean sigma sqrt(pi/2).
  EXPECT_NEAR(mean_angle, std::atan(std::tan(15 * kPi / 180) * std::sqrt(kPi / 2)) * 180 / kPi, 1.0);
  pnf::SyntheticCloud same = pnf::make_scanned_house(20000, pnf::ScanNoise{0.1, 15, 4});
  EXPECT_EQ(same.cloud.positions, house.cloud.positions) << "same seed, same cloud";
}

}  // namespace
