// --auto's fallback on noisy positions (lib/src/auto/judged_passes.hpp, tries_fallback): where
// the judged settings keep the input and the positions are not clean, one wide pass at the
// paper's sigma_f is judged against the input's score less the judge's own error in quadrature;
// its counterpart on clean positions, the narrow pass for plane-fit normals; and where both keep
// the input of plane-fit normals on noisy positions, the held-out check (held_out_planes.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "auto/judged_passes.hpp"
#include "auto/surface_judge.hpp"
#include "crease_clouds.hpp"
#include "pnf/improve_normals_auto.hpp"
#include "pnf/synthetic_shapes.hpp"

namespace pnf::test {
namespace {

// The scanned house (`points` points, `position_noise` spacings of position noise) with PCA normals
// over k points, turned to the true side.
struct NoisyHouse {
  PointCloud cloud;
  std::vector<Vec3> truth;
};
NoisyHouse noisy_house(int k, double position_noise = 0.5, std::size_t points = 6000) {
  ScanNoise noise;
  noise.position = position_noise;
  const SyntheticCloud house = make_scanned_house(points, noise);
  NoisyHouse h{house.cloud, house.true_normals};
  EstimateParams params;
  params.k = k;
  params.orientation = Orientation::outward;
  h.cloud.normals = estimate_normals(h.cloud.positions, params);
  for (std::size_t i = 0; i < h.truth.size(); ++i) {
    const Vec3 n = h.cloud.normals[i];
    if (dot(n, h.truth[i]) < 0) h.cloud.normals[i] = {-n[0], -n[1], -n[2]};
  }
  return h;
}

// The largest angle (degrees) between --auto's normals `out` and a plain run of the setting it
// kept (run.choice.params, its passes): the same passes, but a plain run divides its output by its
// length once more, in double.
double angle_from_plain_run(NormalFilter& filter, const PointCloud& cloud, const AutoRun& run,
                            const std::vector<Vec3>& out) {
  std::vector<Vec3> direct(cloud.size());
  filter.run(cloud, MutableVec3ArrayView(direct), run.choice.params);
  double most = 0;
  for (std::size_t i = 0; i < out.size(); ++i) most = std::max(most, angle_deg(out[i], direct[i]));
  return most;
}

// The rule's passes over PCA-16 normals of the noisy house stay above the judge's full bar; the
// fallback's one pass beats the input's score less the judge's own error, and is kept: the
// fallback's own run, and truly better than the input.
TEST(NoisyFallback, KeepsItsPassWhereTheJudgeVouchesForIt) {
  NoisyHouse h = noisy_house(16);
  NormalFilter& filter = fastest_filter();
  std::vector<Vec3> out(h.cloud.size());
  const AutoRun run = improve_normals_auto(h.cloud, MutableVec3ArrayView(out), filter);
  const std::string& judged = run.choice.judged;
  ASSERT_NE(judged.find("; fallback sigma_f 4, sigma_g 2"), std::string::npos) << judged;
  EXPECT_NE(judged.find(": the fallback, 1 pass kept"), std::string::npos) << judged;
  EXPECT_EQ(run.passes_kept, 1);
  EXPECT_EQ(run.choice.params.sigma_f, FilterParams().sigma_f);
  EXPECT_EQ(run.choice.params.sigma_g, FilterParams().sigma_f / 2);
  EXPECT_EQ(run.choice.params.units, Units::radius);
  EXPECT_EQ(run.choice.params.iterations, 1);
  EXPECT_LT(angle_from_plain_run(filter, h.cloud, run, out), 1e-9) << "the kept normals are not the fallback's own run";
  EXPECT_LT(rms_line_angle(out, h.truth), 0.9 * rms_line_angle(h.cloud.normals, h.truth));
}

// At 0.8 spacings of noise the judge's fits hold 1025 points, about three of the fallback's
// passes' reach: over PCA-16 normals (plane fits) the fallback's passes are judged as far as that
// (judged_passes.hpp, fallback_pass_budget) and three are kept, a plain run of the fallback's
// setting, truer than its first pass alone (all the fallback ran before).
TEST(NoisyFallback, PlaneFitsGetThePassesTheJudgesFitsHold) {
  NoisyHouse h = noisy_house(16, 0.8);
  NormalFilter& filter = fastest_filter();
  std::vector<Vec3> out(h.cloud.size());
  const AutoRun run = improve_normals_auto(h.cloud, MutableVec3ArrayView(out), filter);
  ASSERT_NE(run.choice.judged.find(": the fallback, 3 passes kept"), std::string::npos) << run.choice.judged;
  EXPECT_EQ(run.choice.params.iterations, 3);
  EXPECT_LT(angle_from_plain_run(filter, h.cloud, run, out), 1e-9) << "the kept normals are not the fallback's own run";
  FilterParams one_pass = run.choice.params;
  one_pass.iterations = 1;
  std::vector<Vec3> first(h.cloud.size());
  filter.run(h.cloud, MutableVec3ArrayView(first), one_pass);
  EXPECT_LT(rms_line_angle(out, h.truth), rms_line_angle(first, h.truth));
}

// One pass reaches the points within 2 sigma_f: pi (2 sigma_f)^2 over the area spacing squared.
// The fallback runs one pass, or for plane fits as many as the judge's fits hold (their points over
// one pass's reach), at most kFallbackPlaneFitPasses.
TEST(NoisyFallback, PassesForPlaneFitsAsManyAsTheJudgesFitsHold) {
  AutoChoice choice;
  choice.estimate.area_spacing = 1;
  choice.estimate.mean_radius = 1.5;
  choice.estimate.position_noise = 0.5;
  ASSERT_TRUE(detail::tries_fallback(choice));
  // sigma_f 4 mean radii = 6 spacings, reach 12 spacings: 452.4 points.
  const double reach = 3.14159265358979 * 12 * 12;
  EXPECT_NEAR(detail::pass_reach_points(choice, detail::fallback_setting(choice)), reach, 1e-9 * reach);
  EXPECT_EQ(detail::fallback_pass_budget(choice, 0, 4097), 1);  // no plane fits
  EXPECT_EQ(detail::fallback_pass_budget(choice, 16, 257), 1);
  EXPECT_EQ(detail::fallback_pass_budget(choice, 16, 1025), 2);
  EXPECT_EQ(detail::fallback_pass_budget(choice, 64, 1400), 3);
  EXPECT_EQ(detail::fallback_pass_budget(choice, 16, 4097), detail::kFallbackPlaneFitPasses);
  EXPECT_EQ(detail::fallback_of(choice, 16, 1025, 5, 3).params.iterations, 2);
  EXPECT_EQ(detail::fallback_of(choice, 0, 1025, 5, 3).params.iterations, 1);
}

// On two spacings of noise with PCA-32 normals (plane fits), where the judge and the fallback keep
// the input, the held-out check (held_out_planes.hpp) keeps a pass, which is a plain run of its
// setting and truly better than the input. 9000 points: the judge's fits of 4097 hold under half.
// (With PCA-16 normals the fallback's passes there are kept since fallback_pass_budget: 43.8 deg
// in, 28.6 out.)
TEST(NoisyFallback, TheHeldOutCheckDecidesWhereTheFallbackMisses) {
  NoisyHouse h = noisy_house(32, 2.0, 9000);
  NormalFilter& filter = fastest_filter();
  std::vector<Vec3> out(h.cloud.size());
  const AutoRun run = improve_normals_auto(h.cloud, MutableVec3ArrayView(out), filter);
  const std::string& judged = run.choice.judged;
  ASSERT_NE(judged.find("; fallback sigma_f 4"), std::string::npos) << judged;
  ASSERT_NE(judged.find("; held-out check against the planes"), std::string::npos) << judged;
  EXPECT_NE(judged.find(": the held-out check's pass"), std::string::npos) << judged;
  ASSERT_GT(run.passes_kept, 0);
  EXPECT_EQ(run.choice.params.iterations, run.passes_kept);
  EXPECT_LT(angle_from_plain_run(filter, h.cloud, run, out), 1e-9) << "the kept normals are not the setting's own run";
  EXPECT_LT(rms_line_angle(out, h.truth), 0.95 * rms_line_angle(h.cloud.normals, h.truth));
  EXPECT_LT(mean_angle_deg(out, h.truth), 0.95 * mean_angle_deg(h.cloud.normals, h.truth));
}

// The same house at 6000 points: the judge's fits of 4097 points hold more than half the cloud and
// vouch for no pass (judged_passes.hpp, judge_fits_too_wide); the held-out check alone decides,
// over the rule's setting and the fallback's, and its pass is truly better than the input.
TEST(NoisyFallback, TheHeldOutCheckAloneDecidesWhereTheJudgesFitsHoldHalfTheCloud) {
  NoisyHouse h = noisy_house(16, 2.0);
  NormalFilter& filter = fastest_filter();
  std::vector<Vec3> out(h.cloud.size());
  const AutoRun run = improve_normals_auto(h.cloud, MutableVec3ArrayView(out), filter);
  const std::string& judged = run.choice.judged;
  ASSERT_NE(judged.find("(fits of 4097 points, more than half of the"), std::string::npos) << judged;
  EXPECT_EQ(judged.find("its own error"), std::string::npos) << "the judge scored the passes: " << judged;
  EXPECT_EQ(judged.find("; fallback"), std::string::npos) << judged;
  EXPECT_NE(judged.find(": the held-out check's pass"), std::string::npos) << judged;
  ASSERT_GT(run.passes_kept, 0);
  EXPECT_LT(angle_from_plain_run(filter, h.cloud, run, out), 1e-9) << "the kept normals are not the setting's own run";
  EXPECT_LT(rms_line_angle(out, h.truth), rms_line_angle(h.cloud.normals, h.truth));
  EXPECT_LT(mean_angle_deg(out, h.truth), mean_angle_deg(h.cloud.normals, h.truth));
}

// The same house with its true normals tilted by 10 degrees (no plane fits, so no held-out check):
// the input comes back as it went in, with the rule's setting's summary.
TEST(NoisyFallback, KeepsTheInputWhereTheJudgesFitsHoldHalfTheCloud) {
  NoisyHouse h = noisy_house(16, 2.0);
  std::mt19937 rng(7);
  for (std::size_t i = 0; i < h.truth.size(); ++i) h.cloud.normals[i] = jitter_normal(h.truth[i], 10, rng);
  std::vector<Vec3> out(h.cloud.size());
  const AutoRun run = improve_normals_auto(h.cloud, MutableVec3ArrayView(out), fastest_filter());
  const std::string& judged = run.choice.judged;
  EXPECT_NE(judged.find("more than half of the"), std::string::npos) << judged;
  EXPECT_NE(judged.find(": the input normals kept"), std::string::npos) << judged;
  EXPECT_EQ(run.passes_kept, 0);
  EXPECT_EQ(run.summary.passes_run, 0);
  EXPECT_GT(run.summary.sigma_f, 0);
  double most = 0;
  for (std::size_t i = 0; i < out.size(); ++i) most = std::max(most, angle_deg(out[i], h.cloud.normals[i]));
  EXPECT_LT(most, 1e-6);  // kept normals come back unit length: rounding only
}

// More than half the cloud's points, and only then.
TEST(NoisyFallback, JudgesFitsTooWideFromMoreThanHalfTheCloud) {
  EXPECT_FALSE(detail::judge_fits_too_wide(3000, 6000));
  EXPECT_TRUE(detail::judge_fits_too_wide(3001, 6000));
  EXPECT_FALSE(detail::judge_fits_too_wide(4097, 100000));
}

// Only where the positions are not clean (the judge's quarter refused), and its bar is the
// input's score with the judge's own error taken out in quadrature.
TEST(NoisyFallback, OnlyOnNoisyPositionsAndBelowTheInputLessTheJudgesError) {
  AutoChoice choice;
  choice.estimate.area_spacing = 1;
  choice.estimate.position_noise = 0.05;
  EXPECT_FALSE(detail::tries_fallback(choice));
  choice.estimate.position_noise = 0.1;
  EXPECT_TRUE(detail::tries_fallback(choice));
  EXPECT_DOUBLE_EQ(detail::fallback_to_beat(5, 3), 4);
  EXPECT_EQ(detail::fallback_to_beat(3, 5), 0);
  EXPECT_LT(detail::rms_to_beat(5, 3), detail::fallback_to_beat(5, 3));
}

// The narrow pass is the clean positions' fallback, and only for plane-fit input normals; its bar
// is the input's score plus the judge's own error. The noisy fallback needs no plane fits.
TEST(NoisyFallback, NarrowPassOnlyOnCleanPositionsForPlaneFits) {
  AutoChoice choice;
  choice.estimate.area_spacing = 1;
  choice.estimate.position_noise = 0.05;
  EXPECT_FALSE(detail::tries_narrow_pass(choice, 0));
  ASSERT_TRUE(detail::tries_narrow_pass(choice, 16));
  const detail::Fallback narrow = detail::fallback_of(choice, 16, 257, 5, 3);
  EXPECT_EQ(narrow.candidate, detail::kNarrowPassCandidate);
  EXPECT_DOUBLE_EQ(narrow.to_beat, 8);
  EXPECT_EQ(narrow.params.sigma_f, detail::smooth_detail_setting(choice).sigma_f);
  EXPECT_EQ(narrow.params.iterations, 1);
  EXPECT_EQ(detail::fallback_of(choice, 0, 257, 5, 3).candidate, 0u);
  choice.estimate.position_noise = 0.1;
  EXPECT_FALSE(detail::tries_narrow_pass(choice, 16));
  const detail::Fallback wide = detail::fallback_of(choice, 16, 257, 5, 3);
  EXPECT_EQ(wide.candidate, detail::kFallbackCandidate);
  EXPECT_DOUBLE_EQ(wide.to_beat, 4);
}

// The held-out check runs on noisy positions, for plane-fit input normals, where Stein's estimate
// does not decide; its settings are the rule's (with the judge's budget) and the fallback's, with up
// to kJudgedPassBudget passes.
TEST(NoisyFallback, HeldOutCheckOnlyOnNoisyPositionsForPlaneFits) {
  AutoChoice choice;
  choice.estimate.area_spacing = 1;
  choice.estimate.position_noise = 0.05;
  EXPECT_FALSE(detail::tries_held_out(choice, 16));
  choice.estimate.position_noise = 0.1;
  EXPECT_FALSE(detail::tries_held_out(choice, 0));
  ASSERT_TRUE(detail::tries_held_out(choice, 16));
  const std::vector<FilterParams> settings = detail::held_out_settings(choice, 4097);
  ASSERT_EQ(settings.size(), 2u);
  EXPECT_EQ(settings[0].sigma_f, choice.params.sigma_f);
  EXPECT_EQ(settings[0].iterations, detail::judged_pass_budget(choice.params, choice, 4097));
  EXPECT_EQ(settings[1].sigma_g, detail::fallback_setting(choice).sigma_g);
  EXPECT_EQ(settings[1].iterations, detail::kJudgedPassBudget);
  // Where Stein's estimate decides (independent errors with a measured noise), it does not.
  choice.estimate.points = 100000;
  choice.estimate.normal_noise_deg = 10;
  choice.estimate.normal_noise_neighbours_deg = 10;
  ASSERT_TRUE(detail::stein_decides(choice));
  EXPECT_FALSE(detail::tries_held_out(choice, 16));
}

}  // namespace
}  // namespace pnf::test
