// --auto on noisy positions with input normals whose own noise is under the judge's error
// (lib/src/auto/judged_passes.hpp, judge_cannot_see_gains, and the floor that noise puts under the
// judge's error, judge_error_deg): exact normals come back as they went in, and only there; plane
// fits (PCA) and normals with independent noise are judged as before.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "auto/judged_passes.hpp"
#include "crease_clouds.hpp"
#include "pnf/choose_filter_params.hpp"
#include "pnf/improve_normals_auto.hpp"
#include "pnf/synthetic_shapes.hpp"
#include "test_clouds.hpp"

namespace pnf::test {
namespace {

// The scanned house (6000 points) at `position_noise` spacings, with its exact normals.
SyntheticCloud house_with_exact_normals(double position_noise) {
  ScanNoise noise;
  noise.position = position_noise;
  SyntheticCloud house = make_scanned_house(6000, noise);
  house.cloud.normals = house.true_normals;
  return house;
}

// The same house with PCA normals over `k` points (outward).
SyntheticCloud house_with_pca_normals(int k) {
  SyntheticCloud house = house_with_exact_normals(0.5);
  EstimateParams pca;
  pca.k = k;
  pca.orientation = Orientation::outward;
  house.cloud.normals = estimate_normals(house.cloud.positions, pca);
  return house;
}

// --auto on `cloud`, expected to keep its input normals without a pass (judge_cannot_see_gains).
void expect_kept_without_a_pass(const PointCloud& cloud) {
  std::vector<Vec3> out(cloud.size());
  const AutoRun run = improve_normals_auto(cloud, MutableVec3ArrayView(out), fastest_filter());
  SCOPED_TRACE(run.choice.rule + "; " + run.choice.judged);
  EXPECT_NE(run.choice.judged.find("no pass could be judged"), std::string::npos);
  EXPECT_EQ(run.passes_kept, 0);
  EXPECT_EQ(run.choice.params.iterations, 0);
  // The summary is the rule's setting's, as where the rule chooses no pass: the radius and sigmas.
  EXPECT_EQ(run.summary.points, cloud.size());
  EXPECT_GT(run.summary.sigma_f, 0);
  EXPECT_EQ(run.summary.passes_run, 0);
  double most = 0;
  for (std::size_t i = 0; i < out.size(); ++i) most = std::max(most, angle_deg(out[i], cloud.normals[i]));
  EXPECT_LT(most, 1e-6);  // kept normals come back unit length: rounding only
}

// The house at half a spacing of noise with its exact normals: the judge read them 11.2 deg from
// its fits with its own error at 1.8 deg, and kept the fallback's wide pass (0 deg in, 3.0 out).
// Their own noise reads 0: no pass can be judged, and they come back as they went in.
TEST(UnseenGains, ExactNormalsOnNoisyPositionsAreKept) {
  expect_kept_without_a_pass(house_with_exact_normals(0.5).cloud);
}

// PCA normals over 64 points of the same house nudged by a hundredth of a degree: smooth, and no
// plane fits of any count, their own noise (0.95 deg) under the judge's error (3.95): kept without
// a pass (before, the fallback's pass was judged and missed its bar, with the same outcome).
TEST(UnseenGains, SmoothNormalsThatAreNoPlaneFitsAreKept) {
  SyntheticCloud house = house_with_pca_normals(64);
  std::mt19937 rng(5);
  for (Vec3& n : house.cloud.normals) n = jitter_normal(n, 0.01, rng);
  expect_kept_without_a_pass(house.cloud);
}

// The test itself: on noisy positions only, for normals that are no plane fits, whose own noise
// (the lower of the two readings) was measured and is under the judge's own error.
TEST(UnseenGains, OnlyOnNoisyPositionsForMeasuredNoiseUnderTheJudgesErrorWithoutPlaneFits) {
  AutoChoice noisy = choose_filter_params(estimate_data(house_with_exact_normals(0.5).cloud));
  ASSERT_TRUE(detail::tries_fallback(noisy));
  ASSERT_FALSE(detail::stein_decides(noisy));
  noisy.estimate.normal_noise_neighbours_deg = 1.0;
  EXPECT_TRUE(detail::judge_cannot_see_gains(noisy, 0, 2.0));
  EXPECT_FALSE(detail::judge_cannot_see_gains(noisy, 0, 0.5));   // the noise above the judge's error
  EXPECT_FALSE(detail::judge_cannot_see_gains(noisy, 16, 2.0));  // PCA normals over 16 points
  noisy.estimate.normal_noise_neighbours_deg = 3.0;
  noisy.estimate.normal_noise_chords_deg = 1.0;  // the lower reading is the noise (stein_noise_deg)
  EXPECT_TRUE(detail::judge_cannot_see_gains(noisy, 0, 2.0));
  noisy.estimate.normal_noise_neighbours_deg = -1;  // not measured
  EXPECT_FALSE(detail::judge_cannot_see_gains(noisy, 0, 2.0));
  AutoChoice clean = choose_filter_params(estimate_data(house_with_exact_normals(0).cloud));
  ASSERT_FALSE(detail::tries_fallback(clean));
  clean.estimate.normal_noise_neighbours_deg = 1.0;
  EXPECT_FALSE(detail::judge_cannot_see_gains(clean, 0, 2.0));
}

// The floor under the judge's error: where the input's errors are independent of the judge's fits,
// its judged RMS D holds its noise s and the judge's error in quadrature (3, 4, 5); the judge's own
// error where higher, or where no noise bounds it (below 0) or the noise alone exceeds D.
TEST(UnseenGains, TheInputsOwnNoiseBoundsTheJudgesErrorFromBelow) {
  EXPECT_NEAR(detail::judge_error_deg(5, 1, 3), 4, 1e-12);
  EXPECT_NEAR(detail::judge_error_deg(5, 4.5, 3), 4.5, 1e-12);
  EXPECT_NEAR(detail::judge_error_deg(5, 1, -1), 1, 1e-12);
  EXPECT_NEAR(detail::judge_error_deg(3, 1, 5), 1, 1e-12);
  // Only where the judge decides on noisy positions and the input normals are no plane fits.
  AutoChoice noisy = choose_filter_params(estimate_data(house_with_exact_normals(0.5).cloud));
  noisy.estimate.normal_noise_neighbours_deg = 3.0;
  noisy.estimate.normal_noise_chords_deg = 2.0;
  EXPECT_EQ(detail::noise_bounding_judge_deg(noisy, 0), 2.0);  // the lower reading (stein_noise_deg)
  EXPECT_EQ(detail::noise_bounding_judge_deg(noisy, 16), -1);  // PCA normals over 16 points
  AutoChoice clean = choose_filter_params(estimate_data(house_with_exact_normals(0).cloud));
  clean.estimate.normal_noise_neighbours_deg = 3.0;
  EXPECT_EQ(detail::noise_bounding_judge_deg(clean, 0), -1);
}

// PCA normals on the same positions are plane fits: judged as before, and the fallback's pass,
// truly better, is kept (NoisyFallback.KeepsItsPassWhereTheJudgeVouchesForIt has the numbers).
TEST(UnseenGains, PlaneFitNormalsAreStillJudged) {
  const SyntheticCloud house = house_with_pca_normals(16);
  std::vector<Vec3> out(house.cloud.size());
  const AutoRun run = improve_normals_auto(house.cloud, MutableVec3ArrayView(out), fastest_filter());
  EXPECT_EQ(run.choice.judged.find("no pass could be judged"), std::string::npos) << run.choice.judged;
  EXPECT_GT(run.passes_kept, 0) << run.choice.judged;
}

}  // namespace
}  // namespace pnf::test
