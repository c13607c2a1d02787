// pnf::choose_filter_params: the rule's shape and errors, and `pnf filter --auto` end to end.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "cli/cli_test_support.hpp"
#include "noisy_clouds.hpp"
#include "pnf/choose_filter_params.hpp"
#include "pnf/error.hpp"
#include "pnf/mean_radius.hpp"
#include "pnf/point_file.hpp"
#include "test_clouds.hpp"

namespace pnf::test {
namespace {

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

// ---- pnf filter --auto --------------------------------------------------------------------

TEST_F(CliTest, FilterAutoPrintsTheEstimateAndImproves) {
  const Noisy n = noisy_sphere(6000, 0.3, 10, 21);
  const std::string in = write_cloud("sphere.ply", n.cloud);
  const CliRun r = run({"filter", in, path("out.ply"), "--auto", "--backend", "reference"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  for (const char* piece :
       {"spacing", "position noise", "normal noise", "crease length", "chose", "sigma_f", "passes kept", "judged"}) {
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
