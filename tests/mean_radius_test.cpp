#include "pnf/mean_radius.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "pnf/error.hpp"
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

// The figures the header states: a jittered grid gives h within a few percent, uniform random
// samples of one point per h^2 about 0.8 h.
TEST(MeanRadius, StatedFiguresHold) {
  for (auto [jitter, expected] : {std::pair{0.1, 1.00}, std::pair{0.25, 1.00}, std::pair{0.5, 0.94}}) {
    EXPECT_NEAR(pnf::estimate_mean_radius(pnf::test::jittered_grid(200, 1.0, jitter, 3).positions), expected, 0.01)
        << "jitter " << jitter;
  }
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(0, 200);
  std::vector<pnf::Vec3> p;
  for (int i = 0; i < 40000; ++i) p.push_back({u(rng), u(rng), 0});
  EXPECT_NEAR(pnf::estimate_mean_radius(p), 0.80, 0.01);
}

// The one rule: given, else the radius property's mean, else the estimate; an estimate that
// cannot be made is an error.
TEST(MeanRadius, GivenThenPropertyThenEstimate) {
  pnf::PointCloud grid = pnf::test::jittered_grid(30, 0.5, 0.1, 4);
  const pnf::MeanRadius estimated = pnf::mean_radius(grid);
  EXPECT_EQ(estimated.source, pnf::RadiusSource::estimate);
  EXPECT_EQ(estimated.value, pnf::estimate_mean_radius(grid.positions));
  grid.radii.assign(grid.size(), 0.25);
  EXPECT_EQ(pnf::mean_radius(grid).source, pnf::RadiusSource::property);
  EXPECT_DOUBLE_EQ(pnf::mean_radius(grid).value, 0.25);
  EXPECT_EQ(pnf::mean_radius(grid, 2.0).source, pnf::RadiusSource::given);
  EXPECT_EQ(pnf::mean_radius(grid, 2.0).value, 2.0);
  const std::vector<pnf::Vec3> same(100, pnf::Vec3{3, 4, 5});
  EXPECT_THROW(pnf::mean_radius(pnf::CloudView(same)), pnf::Error);
}

// The filter's frame: the estimate does not depend on the order of the input rows.
TEST(MeanRadius, InputOrderDoesNotMatter) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0, 10);
  std::vector<pnf::Vec3> p;
  for (int i = 0; i < 150000; ++i) p.push_back({u(rng), u(rng), 0.01 * u(rng)});  // > 100k: sampled
  std::vector<pnf::Vec3> reversed(p.rbegin(), p.rend());
  EXPECT_EQ(pnf::estimate_mean_radius(p), pnf::estimate_mean_radius(reversed));
}

// ... nor does the mean of the radius property: the radii are summed exactly (exact_sum.hpp).
TEST(MeanRadius, PropertyMeanHasTheSameBitsInAnyRowOrder) {
  pnf::PointCloud cloud = pnf::test::jittered_grid(100, 0.5, 0.1, 5);
  std::mt19937 rng(10);
  std::lognormal_distribution<double> radius(-1, 0.7);
  for (std::size_t i = 0; i < cloud.size(); ++i) cloud.radii.push_back(radius(rng));
  const double mean = pnf::mean_radius(cloud).value;
  bool rounding_moves = false;  // a plain sum in another order would round differently
  for (unsigned seed : {1u, 2u, 3u}) {
    std::vector<std::size_t> order(cloud.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::shuffle(order.begin(), order.end(), std::mt19937(seed));
    pnf::PointCloud shuffled;
    double plain = 0;
    for (std::size_t i : order) {
      shuffled.positions.push_back(cloud.positions[i]);
      shuffled.normals.push_back(cloud.normals[i]);
      shuffled.radii.push_back(cloud.radii[i]);
      plain += cloud.radii[i];
    }
    EXPECT_EQ(pnf::mean_radius(shuffled).value, mean) << "seed " << seed;
    rounding_moves = rounding_moves || plain / double(cloud.size()) != mean;
    EXPECT_NEAR(plain / double(cloud.size()), mean, 1e-12 * mean);
  }
  EXPECT_TRUE(rounding_moves) << "the test's orders do not exercise the rounding";
}

}  // namespace
