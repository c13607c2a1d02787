// pnf::choose_filter_params on mostly flat shapes with a few creases (issue 14): `--auto` must
// keep a rare crease and never return normals worse than its input, and its choice must not
// depend on how densely the same surface is sampled. The answers are the shapes' true normals,
// known from their construction, not anything the rule computes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "crease_clouds.hpp"
#include "pnf/choose_filter_params.hpp"
#include "pnf/error.hpp"
#include "pnf/estimate_normals.hpp"
#include "pnf/normal_filter.hpp"
#include "test_backends.hpp"
#include "test_clouds.hpp"

namespace pnf::test {
namespace {

// issue 14's target: --auto within 10% of the best fixed setting.
constexpr double kWithinOfAFixedSetting = 1.10;

// A crease with PCA-16 normals, --auto's choice for it, and the RMS line angles to the truth of
// its input, of --auto's normals and of the paper's settings (FilterParams' defaults).
struct AutoOnCrease {
  AutoChoice choice;
  double input = 0, filtered = 0, paper = 0;
};

// The RMS line angle to the truth of the crease's normals filtered at `params`.
double rms_after(const Crease& c, const FilterParams& params) {
  return rms_line_angle(fastest_filter().run(c.cloud, params).normals, c.truth);
}

// A setting of the evaluation's grid (mean radii, the paper's units).
FilterParams grid_setting(double sigma_f, double sigma_g, int passes) {
  FilterParams params;
  params.sigma_f = sigma_f;
  params.sigma_g = sigma_g;
  params.iterations = passes;
  return params;
}

AutoOnCrease auto_on_crease(double degrees, int points, double noise, unsigned seed) {
  Crease c = make_crease(degrees, points, noise, seed);
  c.cloud.normals = pca16_normals(c.cloud.positions, c.truth);
  AutoOnCrease run;
  run.choice = choose_filter_params(c.cloud);
  run.input = rms_line_angle(c.cloud.normals, c.truth);
  run.filtered = rms_after(c, run.choice.params);
  run.paper = rms_after(c, FilterParams{});
  return run;
}

// The case: 90 degrees, 100k points, 0.1 spacings of noise, PCA normals. Before the fix
// --auto read "7% of the samples at an edge -> smooth", switched the feature term off and
// returned 6.27 deg RMS against 3.34 for its input (the paper's settings: 1.25).
TEST(AutoCreases, RareNinetyDegreeCreaseIsNotMadeWorse) {
  const AutoOnCrease run = auto_on_crease(90, 100000, 0.1, 14);
  const AutoChoice& choice = run.choice;
  EXPECT_LT(run.filtered, run.input) << choice.rule;
  // The feature term is what keeps the crease: a finite sigma_g (off is 1e6 spacings).
  EXPECT_LT(choice.params.sigma_g, 100.0) << choice.rule;
}

// The second case: a gentle crease (135 degrees) at 20k points and 0.25 spacings of noise
// read "1% edges -> smooth" and gave 4.32 deg against 2.17 for the paper's settings.
TEST(AutoCreases, GentleCreaseIsNotMadeWorse) {
  const AutoOnCrease run = auto_on_crease(135, 20000, 0.25, 15);
  const AutoChoice& choice = run.choice;
  EXPECT_LT(run.filtered, run.input) << choice.rule;
  // The target is 10% of the best fixed setting of the evaluation's grid, of which the
  // paper's is one point: so at most 10% above the paper's.
  EXPECT_LT(run.filtered, kWithinOfAFixedSetting * run.paper) << choice.rule;
  EXPECT_LT(choice.params.sigma_g, 100.0) << choice.rule;
}

// A 120-degree crease at 0.1 spacings of noise, 20k points, PCA normals: the held-out case of
// issue 14 that stayed 1.11 times its grid's best while sigma_g followed 0.2 + 1.5 p (0.35
// spacings, which let the gentle crease blur); the noise's spread in quadrature with the clean
// width gives 0.28 (1.06 on the evaluation's cloud). The answer to beat is the grid's best there
// (8 / 0.25 mean radii, 4 passes).
TEST(AutoCreases, GentleCreaseAtLowNoiseGetsANarrowSigmaG) {
  Crease c = make_crease(120, 20000, 0.1, 33);
  c.cloud.normals = pca16_normals(c.cloud.positions, c.truth);
  const AutoChoice choice = choose_filter_params(c.cloud);
  EXPECT_NE(choice.rule.find("gentle creases"), std::string::npos) << choice.rule;
  const double filtered = rms_after(c, choice.params), fixed = rms_after(c, grid_setting(8, 0.25, 4));
  // This seed's cloud: 1.009 with the quadrature, 1.046 with the line (the evaluation's: 1.056
  // and 1.113); the bound sits between the two, so that the line's return would fail it.
  EXPECT_LT(filtered, 1.03 * fixed) << choice.rule;
}

// A 150-degree crease at 0.1 spacings of noise: the positions' quadrics absorb its kink (crease
// length under 0.15, the smooth line's reading), but the PCA normals on either side of it turn
// away from them, and the rule takes the line for gentle creases. Held-out case of issue 14:
// before the normals were read, the smooth flat line's 8 passes gave 1.26 times the grid's best
// at 20k points (1.20 at 100k); here the best setting of the grid there (8 / 0.25 mean radii, 2
// passes) and the smooth line's own result are the answers to beat. A plane sampled and noised alike reads no such
// crease.
TEST(AutoCreases, FaintCreaseIsSeenInTheNormalsAndKept) {
  Crease c = make_crease(150, 20000, 0.1, 31);
  c.cloud.normals = pca16_normals(c.cloud.positions, c.truth);
  const AutoChoice choice = choose_filter_params(c.cloud);
  EXPECT_LT(choice.estimate.crease_length, 0.15) << "the positions see no crease: " << choice.rule;
  EXPECT_GE(choice.estimate.normal_crease_length, 0.15) << choice.rule;
  EXPECT_NE(choice.rule.find("faint creases"), std::string::npos) << choice.rule;
  const double filtered = rms_after(c, choice.params), fixed = rms_after(c, grid_setting(8, 0.25, 2));
  // The evaluation's cloud of this case came to 1.096 times its grid's best; this seed's cloud
  // to about 1.12 (other draws of the same crease spread by a few per cent), so 1.15 here.
  EXPECT_LT(filtered, 1.15 * fixed) << choice.rule;
  DataEstimate unseen = choice.estimate;  // what the rule chose before it read the normals
  unseen.normal_crease_length = 0;
  const AutoChoice smooth = choose_filter_params(unseen);
  const double smoothed = rms_after(c, smooth.params);
  EXPECT_LT(filtered, 0.95 * smoothed) << choice.rule << "\n" << smooth.rule;
  for (double noise : {0.1, 0.5}) {
    for (int points : {20000, 100000}) {
      Crease plane = make_crease(180, points, noise, 32);
      plane.cloud.normals = pca16_normals(plane.cloud.positions, plane.truth);
      const DataEstimate e = estimate_data(plane.cloud);
      EXPECT_LT(e.normal_crease_length, 0.05) << points << " points, noise " << noise;
      EXPECT_EQ(choose_filter_params(e).rule.find("faint"), std::string::npos) << choose_filter_params(e).rule;
    }
  }
}

// The same surface 4 and 20 times denser gets an equivalent choice: the same branch of the rule
// (feature term on or off, the same passes) and sigmas within kSigmaTolerance of each other in
// the surface's true spacings. Only estimates (no filtering), so 400k points stay quick. The
// normals are the truth jittered by 5 degrees: they only steer the rule on smooth curved shapes.
TEST(AutoCreases, ChoiceDoesNotDependOnTheSamplingDensity) {
  // The sigmas follow the noise estimate (sigma_g = min(0.2 + 1.5 p, sqrt(0.2^2 + (2 p)^2))),
  // which is good to about 10% at these densities (EstimateData tests: within 25% across noise
  // levels); 20% between any two densities leaves room for that and still tells the branches
  // apart (6.5 against 8 spacings, 0.28 against 1e6).
  constexpr double kSigmaTolerance = 0.2;
  struct Shape {
    double degrees, noise;
  };
  for (const Shape shape : {Shape{90, 0.1}, Shape{135, 0.25}, Shape{60, 0.0}}) {
    std::vector<AutoChoice> choices;
    std::vector<double> true_spacings;
    for (int points : {20000, 100000, 400000}) {
      Crease c = make_crease(shape.degrees, points, shape.noise, 16 + unsigned(points / 1000));
      std::mt19937 rng(7);
      for (const Vec3& n : c.truth) c.cloud.normals.push_back(jitter_normal(n, 5, rng));
      choices.push_back(choose_filter_params(c.cloud));
      true_spacings.push_back(c.spacing);
    }
    if (shape.noise < 0.2 && shape.degrees <= 90) {
      // Sharp creases: the measure against the true crease length per size, 1 / sqrt 2 (a crease 1
      // long in an area of 2). The band of edge fits is only about two fit radii wide, and its
      // count varies from sample to sample: here 90 degrees at 0.1 spacings measured 0.89-1.17
      // times the truth at 20k-400k points, 60 degrees clean 1.19-1.87 (sharper folds leave a
      // wider band), the cube in the evaluation 0.75. Within a factor 2 either way is what the
      // rule needs: the line it draws (0.15) is a fifth of this crease's length.
      constexpr double kTrueLength = 0.70710678;
      constexpr double kLowest = 0.5, kHighest = 2.0;
      for (std::size_t i = 0; i < choices.size(); ++i) {
        EXPECT_GT(choices[i].estimate.crease_length, kLowest * kTrueLength) << choices[i].rule;
        EXPECT_LT(choices[i].estimate.crease_length, kHighest * kTrueLength) << choices[i].rule;
      }
    }
    for (std::size_t i = 1; i < choices.size(); ++i) {
      const AutoChoice& a = choices[0];
      const AutoChoice& b = choices[i];
      const std::string what = "crease " + std::to_string(int(shape.degrees)) + " deg, noise " +
                               std::to_string(shape.noise) + ", density " + std::to_string(i) + " against 0:\n  " +
                               a.rule + "\n  " + b.rule;
      EXPECT_EQ(a.params.sigma_g < 100.0, b.params.sigma_g < 100.0) << what;
      EXPECT_EQ(a.params.iterations, b.params.iterations) << what;
      // Sigmas in the true spacings of each cloud: params are in units of params.mean_radius.
      auto in_spacings = [](double sigma, const AutoChoice& c, double spacing) {
        return sigma * c.params.mean_radius / spacing;
      };
      const double fa = in_spacings(a.params.sigma_f, a, true_spacings[0]);
      const double fb = in_spacings(b.params.sigma_f, b, true_spacings[i]);
      EXPECT_NEAR(fb / fa, 1.0, kSigmaTolerance) << what;
      if (a.params.sigma_g < 100.0 && b.params.sigma_g < 100.0) {
        const double ga = in_spacings(a.params.sigma_g, a, true_spacings[0]);
        const double gb = in_spacings(b.params.sigma_g, b, true_spacings[i]);
        EXPECT_NEAR(gb / ga, 1.0, kSigmaTolerance) << what;
      }
    }
  }
}

// The surface of the unit cube sampled uniformly at random (`points` samples), Gaussian position
// noise of `noise` spacings per axis, and the true normals tilted by `rms_degrees` RMS: input
// normals whose errors are independent of the positions and of each other, as from a scanner or
// a mesh, unlike PCA's.
Crease noisy_cube_with_tilted_normals(int points, double noise, double rms_degrees, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u01(0, 1);
  Crease c;
  c.spacing = std::sqrt(6.0 / points);
  std::normal_distribution<double> g(0, noise * c.spacing);
  for (int i = 0; i < points; ++i) {
    const int face = int(6 * u01(rng)) % 6, axis = face / 2;
    Vec3 p, n = {0, 0, 0};
    p[axis] = face % 2;
    n[axis] = face % 2 ? 1 : -1;
    p[(axis + 1) % 3] = u01(rng);
    p[(axis + 2) % 3] = u01(rng);
    c.cloud.positions.push_back({p[0] + g(rng), p[1] + g(rng), p[2] + g(rng)});
    c.truth.push_back(n);
    c.cloud.normals.push_back(jitter_normal(n, rms_degrees / std::sqrt(2.0), rng));  // per tangent axis
  }
  return c;
}

// pnf_eval_auto's tuning case "cube n0.5 jitter4": the lines tuned on PCA normals chose sigma_g
// 0.99 spacings and 8 passes and returned 7.71 deg against 4.00 for the input. The estimate must
// see that the errors are independent of the positions, and the choice must improve the input.
TEST(AutoIndependentNormals, NoisyCubeWithTiltedNormalsIsNotMadeWorse) {
  const Crease c = noisy_cube_with_tilted_normals(20000, 0.5, 4, 23);
  const AutoChoice choice = choose_filter_params(c.cloud);
  EXPECT_NE(choice.rule.find("independent"), std::string::npos) << choice.rule;
  EXPECT_LT(std::fabs(choice.estimate.normal_position_coupling), 0.1) << choice.rule;
  const double input = rms_line_angle(c.cloud.normals, c.truth);
  const double filtered = rms_after(c, choice.params);
  EXPECT_LT(filtered, input) << choice.rule;
  // Measured 2.0 deg in the evaluation (the grid's best 1.65): well under the input's 4.
  EXPECT_LT(filtered, 0.75 * input) << choice.rule;
}

// The crease sharpness follows the dihedral angle and not the density or the noise: sharper
// creases read higher, and the same crease at 20k and 100k points and 0.1 or 0.25 spacings of
// noise within 25% of itself (measured 60 degrees 0.39-0.46, 90 0.092-0.103, 120 0.050-0.055):
// the angles here are 1.8 times or more apart in sharpness, and the rule's line (0.06) sits
// between 120 and 90 degrees. 135 degrees at 0.25 spacings leaves too few edge fits to judge
// (6 and 1), so it is left out.
TEST(AutoCreases, SharpnessFollowsTheAngleNotTheDensity) {
  double last = 1e9;
  for (double degrees : {60.0, 90.0, 120.0}) {
    std::vector<double> readings;
    for (int points : {20000, 100000}) {
      for (double noise : {0.1, 0.25}) {
        Crease c = make_crease(degrees, points, noise, 30 + unsigned(points / 1000));
        readings.push_back(estimate_data(c.cloud).crease_sharpness);
      }
    }
    const double low = *std::min_element(readings.begin(), readings.end());
    const double high = *std::max_element(readings.begin(), readings.end());
    EXPECT_LT(high / low, 1.25) << degrees << " deg: " << low << " to " << high;
    EXPECT_LT(high, last) << degrees << " deg reads no gentler than the sharper crease before it";
    last = low;
  }
}

}  // namespace
}  // namespace pnf::test
