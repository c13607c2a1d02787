// pnf::estimate_data and pnf::choose_filter_params: the estimators against noise injected into
// shapes whose spacing is known, the rule's shape, errors, and `pnf filter --auto` end to end.
#include "pnf/auto_params.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "cli/cli_test_support.hpp"
#include "pnf/error.hpp"
#include "pnf/estimate_normals.hpp"
#include "pnf/mean_radius.hpp"
#include "pnf/point_file.hpp"
#include "test_clouds.hpp"

namespace pnf::test {
namespace {

// The bars: spacing within 10%, position and angular noise within 25%.
constexpr double kSpacingTolerance = 0.10;
constexpr double kNoiseTolerance = 0.25;

// A plane z = 0 sampled uniformly at random: side `side` with `points` samples, so the spacing
// (square root of the area per point) is side / sqrt(points). Positions get Gaussian noise of
// `noise` spacings along z; normals +z, tilted by jitter_normal of `degrees`.
struct Noisy {
  PointCloud cloud;
  std::vector<Vec3> truth;
  double spacing = 0;
};

Noisy random_plane(int points, double noise, double degrees, unsigned seed) {
  std::mt19937 rng(seed);
  const double side = 10.0;
  std::uniform_real_distribution<double> u(0, side);
  Noisy n;
  n.spacing = side / std::sqrt(double(points));
  std::normal_distribution<double> g(0, noise * n.spacing);
  for (int i = 0; i < points; ++i) {
    n.cloud.positions.push_back({u(rng), u(rng), noise > 0 ? g(rng) : 0.0});
    n.truth.push_back({0, 0, 1});
    n.cloud.normals.push_back(degrees > 0 ? jitter_normal({0, 0, 1}, degrees, rng) : Vec3{0, 0, 1});
  }
  return n;
}

// A sphere of radius 5 with `points` random samples, noise along the radius and tilted normals.
Noisy noisy_sphere(int points, double noise, double degrees, unsigned seed) {
  constexpr double kRadius = 5.0;
  Noisy n;
  const PointCloud clean = sphere(points, kRadius, seed);
  n.spacing = std::sqrt(4 * kPi * kRadius * kRadius / points);
  std::mt19937 rng(seed + 1);
  std::normal_distribution<double> g(0, noise * n.spacing);
  for (std::size_t i = 0; i < clean.size(); ++i) {
    const Vec3& d = clean.normals[i];
    const double r = kRadius + (noise > 0 ? g(rng) : 0.0);
    n.cloud.positions.push_back({r * d[0], r * d[1], r * d[2]});
    n.truth.push_back(d);
    n.cloud.normals.push_back(degrees > 0 ? jitter_normal(d, degrees, rng) : d);
  }
  return n;
}

// The same cloud with PCA normals over k neighbours of its positions.
Noisy with_pca_normals(Noisy n, int k) {
  EstimateParams params;
  params.k = k;
  n.cloud.normals = estimate_normals(n.cloud.positions, params);
  return n;
}

double rms_angle(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += angle_deg(a[i], b[i]) * angle_deg(a[i], b[i]);
  return std::sqrt(sum / double(a.size()));
}

void expect_relative(double got, double want, double tolerance, const std::string& what) {
  EXPECT_NEAR(got / want, 1.0, tolerance) << what << ": estimated " << got << ", true " << want;
}

TEST(EstimateData, SpacingOfAGridIsItsStep) {
  const PointCloud grid = jittered_grid(80, 0.5, 0.1, 3);
  const DataEstimate e = estimate_data(grid);
  expect_relative(e.area_spacing, 0.5, kSpacingTolerance, "area spacing");
  EXPECT_LT(e.position_noise, 0.05 * 0.5) << "a flat grid has no noise along the normal";
  EXPECT_LT(e.normal_noise_deg, 0.5);
  EXPECT_EQ(e.points, grid.size());
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
  auto pca_coupling = [&](int k) {
    return estimate_data(with_pca_normals(tilted, k).cloud).normal_position_coupling;
  };
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
  EXPECT_THROW(estimate_data(line), Error);
}

// ---- the rule -----------------------------------------------------------------------------

// A shape with sharp edges (crease length 0.3 per size, twice the smooth line, and the
// sharpness of a cube's), as the estimator reports one, with PCA normals over few neighbours
// (their errors follow the positions).
DataEstimate measured(double noise_spacings, double degrees, double crease_length = 0.3, double curved_share = 0) {
  DataEstimate e;
  e.crease_length = crease_length;
  e.curved_share = curved_share;
  e.area_spacing = 2.0;
  e.mean_radius = 2.0;
  e.position_noise = noise_spacings * e.area_spacing;
  e.normal_noise_deg = degrees;
  e.normal_position_coupling = 0.9;
  e.crease_sharpness = 0.1;
  return e;
}

// Flat faces between sharp creases gain from every pass; between gentle ones (a fold of 125 and
// 145 degrees) the later passes blur the creases, and fewer are run.
TEST(ChooseFilterParams, GentleCreasesGetFewerPasses) {
  for (double noise : {0.0, 0.1, 0.25}) {
    DataEstimate e = measured(noise, 5);
    const AutoChoice sharp = choose_filter_params(e);
    e.crease_sharpness = 0.045;
    const AutoChoice gentle = choose_filter_params(e);
    EXPECT_EQ(sharp.params.iterations, 8) << sharp.rule;
    EXPECT_EQ(gentle.params.iterations, 4) << gentle.rule;
    EXPECT_NE(gentle.rule.find("gentle creases"), std::string::npos) << gentle.rule;
    EXPECT_EQ(gentle.params.sigma_f, sharp.params.sigma_f);
    EXPECT_EQ(gentle.params.sigma_g, sharp.params.sigma_g);
    e.normal_noise_deg = 12;
    EXPECT_EQ(choose_filter_params(e).params.iterations, 8) << "far-off normals need every pass";
  }
}

// Input normals whose errors are independent of the positions and of each other (a scanner's):
// on noisy positions, on shapes with sharp edges or curved faces, a wide sigma_g and one or two
// passes; on clean positions, and on flat faces with gentle creases or none, the lines for PCA
// normals.
TEST(ChooseFilterParams, IndependentNormalErrorsGetAWideSigmaGAndFewPasses) {
  auto independent = [](double noise, double degrees, double crease_length, double curved_share) {
    DataEstimate e = measured(noise, degrees, crease_length, curved_share);
    e.normal_position_coupling = 0.02;
    e.normal_error_correlation = 0.01;
    return e;
  };
  const AutoChoice pca = choose_filter_params(measured(0.25, 5));
  const AutoChoice edges = choose_filter_params(independent(0.25, 5, 0.3, 0));
  EXPECT_NE(edges.rule.find("independent"), std::string::npos) << edges.rule;
  EXPECT_GT(edges.params.sigma_g, 2 * pca.params.sigma_g) << edges.rule << "\n" << pca.rule;
  EXPECT_LT(edges.params.sigma_f, pca.params.sigma_f) << edges.rule << "\n" << pca.rule;
  EXPECT_EQ(edges.params.iterations, 1) << edges.rule;
  EXPECT_EQ(choose_filter_params(independent(0.25, 12, 0.3, 0)).params.iterations, 2);
  const AutoChoice curved = choose_filter_params(independent(0.25, 5, 0, 1));
  EXPECT_GE(curved.params.sigma_g, 1e5) << curved.rule;
  const AutoChoice flat = choose_filter_params(independent(0.25, 5, 0, 0));
  EXPECT_LT(flat.params.sigma_g, 1e5) << "faint creases are kept: " << flat.rule;
  EXPECT_EQ(flat.rule.find("independent"), std::string::npos) << flat.rule;
  DataEstimate gentle = independent(0.25, 5, 0.3, 0);
  gentle.crease_sharpness = 0.045;
  const AutoChoice fold = choose_filter_params(gentle);
  EXPECT_EQ(fold.rule.find("independent"), std::string::npos) << fold.rule;
  EXPECT_EQ(fold.params.iterations, 4) << fold.rule;
  gentle.curved_share = 0.7;  // curved faces between the creases: the line again
  EXPECT_NE(choose_filter_params(gentle).rule.find("independent"), std::string::npos);
  const AutoChoice clean = choose_filter_params(independent(0.0, 5, 0.3, 0));
  EXPECT_EQ(clean.rule.find("independent"), std::string::npos) << clean.rule;
  EXPECT_EQ(clean.params.iterations, 8) << clean.rule;
  DataEstimate smoothed = independent(0.25, 5, 0.3, 0);  // PCA over many neighbours
  smoothed.normal_error_correlation = 0.5;
  EXPECT_EQ(choose_filter_params(smoothed).rule.find("independent"), std::string::npos);
}

// Up to the noise where the feature term goes off, more noise widens both Gaussians.
TEST(ChooseFilterParams, MoreNoiseNeverNarrowsTheFilter) {
  for (double curved_share : {0.0, 0.7}) {
    double last_f = 0, last_g = 0;
    for (double noise : {0.0, 0.1, 0.25, 0.5, 1.0, 1.5, 2.0, 2.9}) {
      const AutoChoice c = choose_filter_params(measured(noise, 5 + 4 * noise, 0.3, curved_share));
      EXPECT_NO_THROW(c.params.validate()) << c.rule;
      EXPECT_GE(c.params.sigma_f, last_f) << c.rule;
      EXPECT_GE(c.params.sigma_g, last_g) << c.rule;
      EXPECT_LT(c.params.sigma_g, 1e5) << "edges are kept below 3 spacings of noise: " << c.rule;
      EXPECT_GE(c.params.sigma_f, 1.6) << c.rule;
      EXPECT_LE(c.params.sigma_f, 12.0) << c.rule;
      EXPECT_EQ(c.params.units, Units::radius);
      EXPECT_EQ(c.params.mean_radius, 2.0) << "sigmas are in the estimated spacing";
      EXPECT_GT(c.params.stop_change_deg, 0) << "auto ends the passes by the stop rule too";
      last_f = c.params.sigma_f;
      last_g = c.params.sigma_g;
    }
  }
}

// Flat faces between edges keep every pass at every noise level. Curved ones start narrower; with
// much crease per area (fandisk's small features) they run fewer passes as the noise grows (later
// passes drift on curved patches and eat the features), with few creases (a capped cylinder)
// four on noisy positions.
TEST(ChooseFilterParams, CurvedFacesGetFewerPassesThanFlatOnes) {
  int last_passes = 1000;
  for (double noise : {0.0, 0.1, 0.25, 0.5, 1.0, 2.0}) {
    const AutoChoice flat = choose_filter_params(measured(noise, 3, 0.3, 0.0));
    const AutoChoice fine = choose_filter_params(measured(noise, 3, 4.5, 0.7));
    const AutoChoice few = choose_filter_params(measured(noise, 3, 0.3, 0.7));
    EXPECT_EQ(flat.params.iterations, 8) << flat.rule;
    EXPECT_LE(fine.params.iterations, last_passes) << fine.rule;
    EXPECT_GE(fine.params.iterations, 2) << fine.rule;
    last_passes = fine.params.iterations;
    EXPECT_NE(fine.rule.find("fine features"), std::string::npos) << fine.rule;
    EXPECT_EQ(few.params.iterations, noise == 0 ? 8 : 4) << few.rule;
    EXPECT_NE(few.rule.find("few creases"), std::string::npos) << few.rule;
    EXPECT_EQ(few.params.sigma_f, fine.params.sigma_f) << "one sigma_f line for curved faces";
  }
  EXPECT_EQ(last_passes, 2);
  EXPECT_LT(choose_filter_params(measured(0, 1, 0.3, 0.7)).params.sigma_f,
            choose_filter_params(measured(0, 1, 0.3, 0.0)).params.sigma_f);
}

// A smooth curved shape: clean positions and normals that already agree with the surface are
// kept as they are; noisier normals get one pass, then two. A plane gains from every pass.
TEST(ChooseFilterParams, SmoothShapesFilterOnlyWhatNeedsIt) {
  const AutoChoice clean = choose_filter_params(measured(0.0, 0.3, 0.0, 1.0));
  EXPECT_EQ(clean.params.iterations, 0) << clean.rule;
  EXPECT_NE(clean.rule.find("no pass"), std::string::npos) << clean.rule;
  EXPECT_EQ(choose_filter_params(measured(0.2, 0.3, 0.0, 1.0)).params.iterations, 1) << "noisy positions";
  EXPECT_EQ(choose_filter_params(measured(0.0, 1.5, 0.0, 1.0)).params.iterations, 1);
  EXPECT_EQ(choose_filter_params(measured(0.2, 8.0, 0.0, 1.0)).params.iterations, 2);
  EXPECT_EQ(choose_filter_params(measured(0.2, 8.0, 0.0, 0.0)).params.iterations, 8) << "a plane";
  DataEstimate smoothed = measured(0.0, 1.0, 0.0, 1.0);  // clean, normals already smoothed
  smoothed.normal_error_correlation = 0.35;
  const AutoChoice refit = choose_filter_params(smoothed);
  EXPECT_LT(refit.params.sigma_g, 1.0) << "the positions re-derive the normals: " << refit.rule;
  EXPECT_LT(refit.params.sigma_f, 8.0) << refit.rule;
  EXPECT_EQ(refit.params.iterations, 1) << refit.rule;
  EXPECT_NE(refit.rule.find("correlation 0.35"), std::string::npos) << refit.rule;
  smoothed.normal_error_correlation = 0.05;
  EXPECT_GE(choose_filter_params(smoothed).params.sigma_g, 1e5) << "independent errors average away";
  smoothed.normal_error_correlation = 0.35;
  smoothed.position_noise = 0.25 * smoothed.area_spacing;
  EXPECT_GE(choose_filter_params(smoothed).params.sigma_g, 1e5) << "noisy positions cannot re-derive the normals";
  DataEstimate no_normals = measured(0.0, -1, 0.0, 1.0);
  EXPECT_GT(choose_filter_params(no_normals).params.iterations, 0) << "nothing says the normals are good";
}

TEST(ChooseFilterParams, CleanDataKeepsEdgesAndNoisyDataDropsTheFeatureTerm) {
  const AutoChoice clean = choose_filter_params(measured(0.0, 1));
  EXPECT_LE(clean.params.sigma_g, 0.5) << clean.rule;
  EXPECT_EQ(clean.params.iterations, 8) << "clean edges sharpen with every pass: " << clean.rule;
  const AutoChoice noisy = choose_filter_params(measured(6.0, 30));
  EXPECT_GE(noisy.params.sigma_g, 1e5) << noisy.rule;
  EXPECT_NE(noisy.rule.find("off"), std::string::npos) << noisy.rule;
  EXPECT_GE(noisy.params.sigma_f, 8.0) << noisy.rule;
}

// Smooth curved shapes drop the feature term; smooth flat ones keep it, wider than shapes with
// edges (a crease too faint to measure may still be there: issue 14).
TEST(ChooseFilterParams, SmoothShapesDropTheFeatureTermOnlyWhenCurved) {
  const AutoChoice curved = choose_filter_params(measured(0.3, 5, 0.01, 1.0));
  EXPECT_GE(curved.params.sigma_g, 1e5) << curved.rule;
  EXPECT_GE(curved.params.sigma_f, 8.0) << curved.rule;
  EXPECT_NE(curved.rule.find("smooth"), std::string::npos) << curved.rule;
  const AutoChoice flat = choose_filter_params(measured(0.3, 5, 0.01, 0.0));
  const AutoChoice edges = choose_filter_params(measured(0.3, 5, 2.0, 0.0));
  EXPECT_LT(flat.params.sigma_g, 1e5) << flat.rule;
  EXPECT_GT(flat.params.sigma_g, edges.params.sigma_g) << flat.rule << "\n" << edges.rule;
  EXPECT_GE(flat.params.sigma_f, 8.0) << flat.rule;
}

// A flat shape whose positions show too little crease but whose input normals show some (gentle
// creases the quadrics absorb) takes the gentle creases' line: the edges' sigma_g and 4 passes.
// Curved shapes and shapes without it keep the smooth lines.
TEST(ChooseFilterParams, FaintCreasesInTheNormalsKeepTheGentleLine) {
  DataEstimate faint = measured(0.1, 2, 0.02, 0);
  faint.normal_crease_length = 0.3;
  faint.crease_sharpness = 0;
  const AutoChoice kept = choose_filter_params(faint);
  const AutoChoice edges = choose_filter_params(measured(0.1, 2, 0.3, 0));
  EXPECT_NE(kept.rule.find("faint creases"), std::string::npos) << kept.rule;
  EXPECT_EQ(kept.params.iterations, 4) << kept.rule;
  EXPECT_EQ(kept.params.sigma_g, edges.params.sigma_g) << kept.rule;
  EXPECT_EQ(kept.params.sigma_f, edges.params.sigma_f) << kept.rule;
  faint.normal_crease_length = 0.1;
  const AutoChoice plane = choose_filter_params(faint);
  EXPECT_NE(plane.rule.find("smooth"), std::string::npos) << plane.rule;
  EXPECT_EQ(plane.params.iterations, 8) << plane.rule;
  EXPECT_GT(plane.params.sigma_g, kept.params.sigma_g) << plane.rule;
  faint.normal_crease_length = 0.3;
  faint.curved_share = 1;
  EXPECT_GE(choose_filter_params(faint).params.sigma_g, 1e5) << "smooth curved: " << choose_filter_params(faint).rule;
}

TEST(ChooseFilterParams, RejectsAMissingSpacing) {
  DataEstimate e;
  EXPECT_THROW(choose_filter_params(e), Error);
  e.mean_radius = 1;
  e.area_spacing = std::nan("");
  EXPECT_THROW(choose_filter_params(e), Error);
  e.area_spacing = 1;
  e.mean_radius = 0;
  EXPECT_THROW(choose_filter_params(e), Error);
  e.mean_radius = 1;
  EXPECT_NO_THROW(choose_filter_params(e));
}

// The rule's lengths are in area spacings; the parameters come out in mean radii, and the model
// lengths (sigma x mean radius) do not depend on which mean radius the cloud has.
TEST(ChooseFilterParams, ModelLengthsDoNotDependOnTheMeanRadius) {
  for (double noise : {0.0, 0.3, 1.0, 4.0}) {
    for (double curved : {0.0, 0.7}) {
      DataEstimate same = measured(noise, 5, 0.3, curved);
      DataEstimate smaller = same;
      smaller.mean_radius = 0.82 * same.area_spacing;  // what random samples give
      const AutoChoice a = choose_filter_params(same), b = choose_filter_params(smaller);
      EXPECT_EQ(b.params.mean_radius, smaller.mean_radius);
      EXPECT_NEAR(b.params.sigma_f * b.params.mean_radius, a.params.sigma_f * a.params.mean_radius,
                  1e-12 * a.params.sigma_f * a.params.mean_radius)
          << b.rule;
      EXPECT_NEAR(b.params.sigma_g * b.params.mean_radius, a.params.sigma_g * a.params.mean_radius,
                  1e-12 * a.params.sigma_g * a.params.mean_radius)
          << b.rule;
      EXPECT_EQ(b.params.iterations, a.params.iterations);
      EXPECT_NE(b.rule.find("mean radii"), std::string::npos) << b.rule;
    }
  }
}

TEST(ChooseFilterParams, FromACloudUsesItsEstimate) {
  const Noisy n = noisy_sphere(8000, 0.3, 6, 9);
  const AutoChoice c = choose_filter_params(n.cloud);
  EXPECT_EQ(c.params.mean_radius, c.estimate.mean_radius);
  EXPECT_EQ(c.estimate.mean_radius, estimate_mean_radius(n.cloud.positions)) << "the one spacing, bit for bit";
  EXPECT_EQ(c.estimate.radius_source, RadiusSource::estimate);
  EXPECT_NEAR(c.estimate.position_noise_area_spacings(), 0.3, 0.3 * kNoiseTolerance);
}

// A radius property wins: it is the mean radius, and the sigmas are converted to it.
TEST(EstimateData, TheRadiusPropertyIsTheMeanRadius) {
  Noisy n = noisy_sphere(5000, 0.2, 5, 3);
  const DataEstimate without = estimate_data(n.cloud);
  n.cloud.radii.assign(n.cloud.size(), 0.0);
  double sum = 0;
  for (std::size_t i = 0; i < n.cloud.size(); ++i) sum += n.cloud.radii[i] = 0.1 + 0.01 * double(i % 7);
  const DataEstimate with = estimate_data(n.cloud);
  EXPECT_EQ(with.radius_source, RadiusSource::property);
  EXPECT_DOUBLE_EQ(with.mean_radius, sum / double(n.cloud.size()));
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

// ---- pnf filter --auto --------------------------------------------------------------------

TEST_F(CliTest, FilterAutoPrintsTheEstimateAndImproves) {
  const Noisy n = noisy_sphere(6000, 0.3, 10, 21);
  const std::string in = write_cloud("sphere.ply", n.cloud);
  const CliRun r = run({"filter", in, path("out.ply"), "--auto", "--backend", "reference"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  for (const char* piece :
       {"spacing", "position noise", "normal noise", "crease length", "chose", "sigma_f", "stop rule", "passes"}) {
    EXPECT_TRUE(contains(r.err, piece)) << "no '" << piece << "' in\n" << r.err;
  }
  const std::vector<Vec3> out = read_point_file(path("out.ply")).cloud().normals;
  EXPECT_LT(rms_angle(out, n.truth), 0.5 * rms_angle(n.cloud.normals, n.truth));
}

TEST_F(CliTest, FilterAutoExcludesExplicitSigmas) {
  const std::string in = write_cloud("plane.ply", random_plane(500, 0.1, 3, 1).cloud);
  const CliRun r = run({"filter", in, path("out.ply"), "--auto", "--sigma-f", "3"});
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_FALSE(std::filesystem::exists(path("out.ply")));
}

// The stop rule from the command line: a clean plane stops changing at once, so far fewer than
// the 20 passes asked for run, and the summary says how many.
TEST_F(CliTest, FilterStopChangeEndsThePassesEarly) {
  const std::string in = write_cloud("plane.ply", random_plane(2000, 0.05, 5, 3).cloud);
  const CliRun r =
      run({"filter", in, path("out.ply"), "--backend", "reference", "--iterations", "20", "--stop-change", "0.5"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_TRUE(contains(r.err, "of at most 20 passes run")) << r.err;
  EXPECT_FALSE(contains(r.err, "passes       20:")) << r.err;
  const CliRun bad = run({"filter", in, path("out2.ply"), "--stop-change", "-1"});
  EXPECT_EQ(bad.exit_code, 2) << bad.describe();
}

}  // namespace
}  // namespace pnf::test
