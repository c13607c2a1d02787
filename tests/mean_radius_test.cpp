#include "pnf/mean_radius.hpp"

#include <gtest/gtest.h>

#include "test_clouds.hpp"

namespace {

TEST(MeanRadius, JitteredGridComesOutWithin25PercentOfTheSpacing) {
  for (double jitter : {0.0, 0.1, 0.25}) {
    for (double h : {0.01, 1.0, 350.0}) {
      pnf::PointCloud grid = pnf::test::jittered_grid(80, h, jitter, 11);
      double r = pnf::estimate_mean_radius(grid.positions);
      EXPECT_NEAR(r, h, 0.25 * h) << "spacing " << h << " jitter " << jitter;
    }
  }
}

TEST(MeanRadius, RandomSamplingOfKnownDensity) {
  // Uniform random points, density 1 per h^2: mean spacing about h, so within the same 25%.
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(0, 100);
  std::vector<pnf::Vec3> p;
  for (int i = 0; i < 10000; ++i) p.push_back({u(rng), u(rng), 0});
  EXPECT_NEAR(pnf::estimate_mean_radius(p), 1.0, 0.25);
}

TEST(MeanRadius, TooFewOrCoincidentPointsGiveZero) {
  EXPECT_EQ(pnf::estimate_mean_radius({}), 0.0);
  EXPECT_EQ(pnf::estimate_mean_radius(std::vector<pnf::Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), 0.0);
  std::vector<pnf::Vec3> same(100, pnf::Vec3{3, 4, 5});
  EXPECT_EQ(pnf::estimate_mean_radius(same), 0.0);
}

}  // namespace
