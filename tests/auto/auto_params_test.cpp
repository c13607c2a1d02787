// pnf::estimate_data: the estimators against noise injected into shapes whose spacing is known.
// The rule and `pnf filter --auto`: choose_filter_params_test.cpp.
#include "pnf/choose_filter_params.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "noisy_clouds.hpp"
#include "pnf/error.hpp"
#include "pnf/estimate_normals.hpp"
#include "pnf/mean_radius.hpp"
#include "pnf/point_file.hpp"
#include "test_clouds.hpp"

namespace pnf::test {
namespace {

TEST(EstimateData, SpacingOfAGridIsItsStep) {
  const PointCloud grid = jittered_grid(80, 0.5, 0.1, 3);
  const DataEstimate e = estimate_data(grid);
  expect_relative(e.area_spacing, 0.5, kSpacingTolerance, "area spacing");
  EXPECT_LT(e.position_noise, 0.05 * 0.5) << "a flat grid has no noise along the normal";
  EXPECT_LT(e.normal_noise_deg, 0.5);
  EXPECT_EQ(e.points, grid.size());
}

// A thin plate: two clean grids 2 spacings apart, whose outward normals face away from each
// other. Every fit reaches the far wall: fitted with it, the gap reads as position noise (the
// residual of a surface between the walls, about half the gap); fitted to the sample's own
// sheet (the neighbours whose normals do not face away from its own), as a single grid's, none.
TEST(EstimateData, TheFarWallOfAThinPartIsNotNoise) {
  const double h = 0.5, gap = 2 * h;
  PointCloud plate = jittered_grid(80, h, 0.1, 3);
  for (Vec3& n : plate.normals) n = {0, 0, -1};
  const PointCloud top = jittered_grid(80, h, 0.1, 4);
  for (std::size_t i = 0; i < top.size(); ++i) {
    const Vec3 p = top.positions[i];
    plate.positions.push_back({p[0], p[1], p[2] + gap});
    plate.normals.push_back({0, 0, 1});
  }
  EXPECT_LT(estimate_data(plate).position_noise, 0.05 * h) << "each wall is a flat grid";
  PointCloud bare = plate;
  bare.normals.clear();
  const double without_normals = estimate_data(bare).position_noise;
  EXPECT_GT(without_normals, 0.3 * gap) << "without normals the walls are one noisy layer";
  // Normals of arbitrary sign (unoriented PCA's) face away from half their neighbours on one
  // sheet too: they tell no sheets apart and the fits keep every point, as without normals.
  PointCloud unoriented = plate;
  std::mt19937 rng(5);
  for (Vec3& n : unoriented.normals) {
    if (rng() % 2) n = {-n[0], -n[1], -n[2]};
  }
  EXPECT_EQ(estimate_data(unoriented).position_noise, without_normals);
}

TEST(EstimateData, PlaneWithKnownNoise) {
  for (double noise : {0.1, 0.3, 1.0, 2.0}) {
    const Noisy n = random_plane(20000, noise, 8, 11);
    const DataEstimate e = estimate_data(n.cloud);
    const std::string at = "plane, noise " + std::to_string(noise) + " spacings";
    expect_relative(e.area_spacing, n.spacing, kSpacingTolerance, at + ", area spacing");
    expect_relative(e.position_noise, noise * n.spacing, kNoiseTolerance, at + ", position noise");
    expect_relative(e.normal_noise_deg, rms_angle(n.cloud.normals, n.truth), kNoiseTolerance, at + ", normal noise");
  }
}

TEST(EstimateData, SphereWithKnownNoise) {
  for (double noise : {0.0, 0.25, 0.5}) {
    for (double degrees : {3.0, 12.0}) {
      const Noisy n = noisy_sphere(20000, noise, degrees, 5);
      const DataEstimate e = estimate_data(n.cloud);
      const std::string at = "sphere, noise " + std::to_string(noise) + ", " + std::to_string(degrees) + " deg";
      expect_relative(e.area_spacing, n.spacing, kSpacingTolerance, at + ", area spacing");
      if (noise > 0) {
        expect_relative(e.position_noise, noise * n.spacing, kNoiseTolerance, at + ", position noise");
      } else {
        EXPECT_LT(e.position_noise, 0.05 * n.spacing) << at << ": curvature mistaken for noise";
      }
      expect_relative(e.normal_noise_deg, rms_angle(n.cloud.normals, n.truth), kNoiseTolerance, at + ", normal noise");
      EXPECT_LT(e.feature_share, 0.08) << at << ": a sphere has no sharp features";
    }
  }
}

// Normals whose errors are independent from point to point correlate near 0; normals tilted by a
// field that changes over tens of spacings near 1; PCA normals lie between, the more so the more
// neighbours they average (their errors come from the neighbourhoods they share).
TEST(EstimateData, NormalErrorCorrelationSeesSmoothedNormals) {
  const Noisy independent = noisy_sphere(20000, 0.0, 2, 9);
  EXPECT_LT(std::fabs(estimate_data(independent.cloud).normal_error_correlation), 0.1);

  Noisy smooth = independent;
  const double wavelength = 30 * smooth.spacing;
  for (std::size_t i = 0; i < smooth.cloud.size(); ++i) {
    const Vec3& p = smooth.cloud.positions[i];
    const Vec3& d = smooth.truth[i];
    // A 2-degree tilt towards a direction that turns slowly with the position.
    const double angle = 2 * kPi * (p[0] + 0.5 * p[1]) / wavelength;
    const Vec3 push = {std::cos(angle), std::sin(angle), 0.3};
    const double along = push[0] * d[0] + push[1] * d[1] + push[2] * d[2];
    const double tilt = std::tan(2.0 * kPi / 180.0);
    Vec3 n;
    for (int k = 0; k < 3; ++k) n[k] = d[k] + tilt * (push[k] - along * d[k]);
    smooth.cloud.normals[i] = normalized(n);
  }
  EXPECT_GT(estimate_data(smooth.cloud).normal_error_correlation, 0.7);

  auto pca_correlation = [&](int k) {
    return estimate_data(with_pca_normals(independent, k).cloud).normal_error_correlation;
  };
  const double pca16 = pca_correlation(16), pca64 = pca_correlation(64);
  EXPECT_LT(pca16, 0.1);
  EXPECT_GT(pca64, pca16 + 0.1) << "PCA-16 " << pca16 << ", PCA-64 " << pca64;  // measured 0.02, 0.20
  PointCloud bare = independent.cloud;
  bare.normals.clear();
  EXPECT_EQ(estimate_data(bare).normal_error_correlation, 0.0) << "no normals, nothing to correlate";
}

// Whether the input normals' errors follow the positions: PCA normals over 16 neighbours of
// these very positions near 1, over 64 far less (they average the noise of many more points),
// the true normals tilted at random near 0.
TEST(EstimateData, NormalPositionCouplingTellsPcaFromIndependentNormals) {
  const Noisy tilted = noisy_sphere(20000, 0.25, 4, 12);
  EXPECT_LT(std::fabs(estimate_data(tilted.cloud).normal_position_coupling), 0.1);
  auto pca_coupling = [&](int k) { return estimate_data(with_pca_normals(tilted, k).cloud).normal_position_coupling; };
  const double pca16 = pca_coupling(16), pca64 = pca_coupling(64);
  EXPECT_GT(pca16, 0.7);  // measured 0.93 (the evaluation's noisy shapes: 0.85-0.94)
  EXPECT_LT(pca64, 0.5 * pca16) << "PCA-16 " << pca16 << ", PCA-64 " << pca64;  // measured 0.17
  PointCloud bare = tilted.cloud;
  bare.normals.clear();
  EXPECT_EQ(estimate_data(bare).normal_position_coupling, 0.0) << "no normals, nothing to compare";
}

// A 90-degree ridge: many samples see the edge; a plane: none.
TEST(EstimateData, FeatureShareSeesEdges) {
  const DataEstimate ridge = estimate_data(wedge(40, 100, 1.0, 0.3, 6));
  EXPECT_GT(ridge.feature_share, 0.15);
  const DataEstimate flat = estimate_data(random_plane(8000, 0.2, 3, 6).cloud);
  EXPECT_LT(flat.feature_share, 0.08);
}

// A torus whose tube is about 9 spacings thick in radius: the largest neighbourhoods hold the
// whole tube and fit it badly everywhere, which must not read as a shape made of edges.
TEST(EstimateData, ThinTubeIsSmoothNotAllEdges) {
  constexpr double kBig = 1.0, kSmall = 0.35;
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> unit(0, 1);
  PointCloud torus;
  while (torus.size() < 10000) {
    const double u = 2 * kPi * unit(rng), v = 2 * kPi * unit(rng);
    // Uniform over the area: the ring at angle v has length proportional to kBig + kSmall cos v.
    if (unit(rng) * (kBig + kSmall) > kBig + kSmall * std::cos(v)) continue;
    const Vec3 n = {std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v)};
    const double ring = kBig + kSmall * std::cos(v);
    torus.positions.push_back({ring * std::cos(u), ring * std::sin(u), kSmall * std::sin(v)});
    torus.normals.push_back(n);
  }
  const DataEstimate e = estimate_data(torus);
  EXPECT_NEAR(kSmall / e.area_spacing, 9.4, 1.0) << "the tube radius in spacings this test is about";
  EXPECT_LT(e.feature_share, 0.08);
  EXPECT_GT(e.curved_share, 0.9);
  EXPECT_LT(e.normal_noise_deg, 0.5) << "exact normals";
}

// Curvature: a sphere of 40 spacings' radius is curved everywhere; a ridge of two planes and a
// noisy plane are flat, noise and the edge notwithstanding.
TEST(EstimateData, CurvedShareTellsCurvedFromFlat) {
  for (double noise : {0.0, 0.5}) {
    const std::string at = "noise " + std::to_string(noise) + " spacings";
    EXPECT_GT(estimate_data(noisy_sphere(20000, noise, 3, 7).cloud).curved_share, 0.9) << at;
    EXPECT_LT(estimate_data(random_plane(20000, noise, 3, 7).cloud).curved_share, 0.05) << at;
  }
  EXPECT_LT(estimate_data(wedge(40, 100, 1.0, 0.3, 6)).curved_share, 0.05) << "ridge";
}

// Moving the cloud far away (as scans are) changes nothing but rounding.
TEST(EstimateData, TranslationChangesNothing) {
  Noisy n = random_plane(5000, 0.3, 5, 2);
  const DataEstimate here = estimate_data(n.cloud);
  for (Vec3& p : n.cloud.positions) p = {p[0] + 1e4, p[1] - 2e4, p[2] + 5e3};
  const DataEstimate there = estimate_data(n.cloud);
  EXPECT_NEAR(there.area_spacing, here.area_spacing, 1e-6 * here.area_spacing);
  EXPECT_NEAR(there.mean_radius, here.mean_radius, 1e-6 * here.mean_radius);
  EXPECT_NEAR(there.position_noise, here.position_noise, 1e-6 * here.area_spacing);
  EXPECT_NEAR(there.normal_noise_deg, here.normal_noise_deg, 1e-4);
}

TEST(EstimateData, WithoutNormalsNoAngularNoise) {
  Noisy n = random_plane(3000, 0.2, 0, 4);
  n.cloud.normals.clear();
  EXPECT_LT(estimate_data(n.cloud).normal_noise_deg, 0);
}

TEST(EstimateData, BadCloudsAreErrors) {
  PointCloud tiny = jittered_grid(3, 1, 0, 1);  // 9 points
  EXPECT_THROW(estimate_data(tiny), Error);
  PointCloud nan = jittered_grid(10, 1, 0, 1);
  nan.positions[7][1] = std::nan("");
  try {
    estimate_data(nan);
    ADD_FAILURE() << "a NaN coordinate was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_input);
    EXPECT_NE(std::string(e.what()).find("vertex 7"), std::string::npos) << e.what();
  }
  PointCloud line;
  for (int i = 0; i < 50; ++i) line.positions.push_back({double(i), 0, 0});
  try {
    estimate_data(line);
    ADD_FAILURE() << "points on a line were fitted";
  } catch (const Error& e) {
    // The message says how many points there were and what a fit needs.
    EXPECT_EQ(e.code(), ErrorCode::invalid_input);
    EXPECT_NE(std::string(e.what()).find("no neighbourhood of the 50 points could be fitted"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("a fit needs 12 points"), std::string::npos) << e.what();
  }
}

// A radius property wins: it is the mean radius, and the sigmas are converted to it.
TEST(EstimateData, TheRadiusPropertyIsTheMeanRadius) {
  Noisy n = noisy_sphere(5000, 0.2, 5, 3);
  const DataEstimate without = estimate_data(n.cloud);
  n.cloud.radii.assign(n.cloud.size(), 0.0);
  for (std::size_t i = 0; i < n.cloud.size(); ++i) n.cloud.radii[i] = 0.1 + 0.01 * double(i % 7);
  const DataEstimate with = estimate_data(n.cloud);
  EXPECT_EQ(with.radius_source, RadiusSource::property);
  // 5000 points: 714 whole cycles of i mod 7 and 0, 1: a mean of 0.1 + 0.01 x 14995 / 5000. The
  // radii are summed exactly (a plain sum of the 5000 is 9 ulps off), so only their own
  // roundings remain, about an ulp.
  EXPECT_NEAR(with.mean_radius, 0.12999, 1e-16);
  EXPECT_EQ(with.mean_radius, mean_radius(n.cloud).value) << "the one mean radius";
  EXPECT_EQ(with.area_spacing, without.area_spacing) << "the rule's own density measure is unchanged";
  EXPECT_EQ(with.position_noise, without.position_noise);
  n.cloud.radii[17] = -1;
  EXPECT_THROW(estimate_data(n.cloud), Error) << "a bad radius is an error";
}

// Views of the caller's memory: float rows and strided rows give the PointCloud's estimate to the
// last bit (float values widen exactly).
TEST(EstimateData, FloatAndStridedViewsGiveTheCloudsEstimate) {
  const Noisy n = noisy_sphere(4000, 0.3, 6, 12);
  struct Row {
    float position[3];
    float pad;
    float normal[3];
  };
  std::vector<Row> rows(n.cloud.size());
  PointCloud widened;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      rows[i].position[c] = float(n.cloud.positions[i][c]);
      rows[i].normal[c] = float(n.cloud.normals[i][c]);
    }
  }
  // A second loop: GCC 12 at -O2 forwards the unrounded double into a push_back in the loop that
  // stores the float (measured), which would make `widened` hold other values than `rows`.
  for (std::size_t i = 0; i < rows.size(); ++i) {
    widened.positions.push_back({rows[i].position[0], rows[i].position[1], rows[i].position[2]});
    widened.normals.push_back({rows[i].normal[0], rows[i].normal[1], rows[i].normal[2]});
  }
  const CloudView view(Vec3ArrayView(rows[0].position, rows.size(), ScalarType::float32, sizeof(Row)),
                       Vec3ArrayView(rows[0].normal, rows.size(), ScalarType::float32, sizeof(Row)));
  const AutoChoice from_cloud = choose_filter_params(widened);
  const AutoChoice from_view = choose_filter_params(view);
  EXPECT_EQ(from_view.estimate.mean_radius, from_cloud.estimate.mean_radius);
  EXPECT_EQ(from_view.estimate.area_spacing, from_cloud.estimate.area_spacing);
  EXPECT_EQ(from_view.estimate.position_noise, from_cloud.estimate.position_noise);
  EXPECT_EQ(from_view.estimate.normal_noise_deg, from_cloud.estimate.normal_noise_deg);
  EXPECT_EQ(from_view.estimate.feature_share, from_cloud.estimate.feature_share);
  EXPECT_EQ(from_view.estimate.curved_share, from_cloud.estimate.curved_share);
  EXPECT_EQ(from_view.estimate.normal_error_correlation, from_cloud.estimate.normal_error_correlation);
  EXPECT_EQ(from_view.params.sigma_f, from_cloud.params.sigma_f);
  EXPECT_EQ(from_view.params.sigma_g, from_cloud.params.sigma_g);
  EXPECT_EQ(from_view.params.iterations, from_cloud.params.iterations);
  EXPECT_EQ(from_view.rule, from_cloud.rule);
}

}  // namespace
}  // namespace pnf::test
