// The passes --auto's judge may run (lib/src/auto/judged_passes.hpp, judged_pass_budget): the
// budget of 8 (or the setting's own passes where more), except on the line for independent
// normal errors, which runs its own one or two passes at most; the settings judged
// (judged_candidates); and when the passes end (judged_passes_end).
#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "auto/judged_passes.hpp"
#include "auto/surface_judge.hpp"
#include "pnf/choose_filter_params.hpp"

namespace pnf::test {
namespace {

// The judge's fits on 100k points: 4097 points.
constexpr int kFits = 4097;

// The rule's choice on an estimate of a curved shape with edges, 100k points, area spacing 0.01
// and mean radius 0.02 model units, 0.5 spacings of noise, normal errors of `normal_noise_deg`
// that are (coupling 0.1, correlation 0.05) or are not (0.9) independent of the positions.
AutoChoice choice_with(double normal_noise_deg, bool independent) {
  DataEstimate e;
  e.points = 100000;
  e.samples = 4000;
  e.area_spacing = 0.01;
  e.mean_radius = 0.02;
  e.position_noise = 0.005;
  e.normal_noise_deg = normal_noise_deg;
  e.normal_position_coupling = independent ? 0.1 : 0.9;
  e.normal_error_correlation = independent ? 0.05 : 0.9;
  e.curved_share = 1;
  e.crease_length = 5;
  e.crease_sharpness = 0.3;
  return choose_filter_params(e);
}

TEST(JudgedPassBudget, TheIndependentErrorsLineRunsItsOwnPasses) {
  // One pass below 9 degrees of normal noise, two from it (the rule's line), never extended.
  for (auto [noise_deg, passes] : {std::pair{5.0, 1}, std::pair{10.0, 2}, std::pair{20.0, 2}}) {
    const AutoChoice choice = choice_with(noise_deg, true);
    ASSERT_TRUE(detail::independent_normal_errors(choice));
    const FilterParams line = detail::independent_errors_setting(choice);
    EXPECT_TRUE(detail::on_independent_errors_line(choice, line));
    EXPECT_EQ(line.iterations, passes) << noise_deg << " deg";
    EXPECT_EQ(detail::judged_pass_budget(line, choice, kFits), passes) << noise_deg << " deg";
  }
}

// Where Stein's estimate decides, plain averaging at the paper's sigma_f runs beside the judged
// settings, for the line's own one or two passes.
TEST(JudgedPassBudget, PlainAveragingRunsTheLinesPassesBesideTheJudgedSettings) {
  for (auto [noise_deg, passes] : {std::pair{5.0, 1}, std::pair{10.0, 2}}) {
    const AutoChoice choice = choice_with(noise_deg, true);
    const std::vector<FilterParams> judged = detail::judged_candidates(choice);
    const std::vector<FilterParams> stein = detail::stein_candidates(choice);
    ASSERT_EQ(stein.size(), judged.size() + 1);
    const FilterParams plain = stein.back();
    EXPECT_EQ(plain.sigma_f, FilterParams().sigma_f);
    EXPECT_GE(plain.sigma_g, 1e5) << "the feature term off";
    EXPECT_EQ(plain.units, Units::radius);
    EXPECT_EQ(plain.iterations, passes);
    EXPECT_EQ(detail::judged_pass_budget(plain, choice, kFits), passes) << noise_deg << " deg";
  }
}

TEST(JudgedPassBudget, OtherSettingsGetTheWholeBudget) {
  // The same cloud, a setting with a tighter sigma_g than the line's: the judge may run 8.
  const AutoChoice choice = choice_with(10, true);
  FilterParams tight = detail::independent_errors_setting(choice);
  tight.sigma_g /= 4;
  EXPECT_FALSE(detail::on_independent_errors_line(choice, tight));
  EXPECT_EQ(detail::judged_pass_budget(tight, choice, kFits), detail::kJudgedPassBudget);
  tight.iterations = 14;  // the setting's own passes, where more than the budget
  EXPECT_EQ(detail::judged_pass_budget(tight, choice, kFits), 14);
}

TEST(JudgedPassBudget, PcaNormalsOnTheLinesSigmasKeepTheWholeBudget) {
  // PCA normals' errors follow the positions: their passes go on while the judge sees gains, even
  // with the line's sigmas (teddy at 0.25% noise, PCA-16: 22.9 deg after one pass, 8.95 after 8).
  const AutoChoice independent = choice_with(10, true);
  const AutoChoice pca = choice_with(10, false);
  ASSERT_FALSE(detail::independent_normal_errors(pca));
  FilterParams params = detail::independent_errors_setting(independent);
  EXPECT_FALSE(detail::on_independent_errors_line(pca, params));
  EXPECT_EQ(detail::judged_pass_budget(params, pca, kFits), detail::kJudgedPassBudget);
}

TEST(JudgedPassBudget, FlatShapesWithoutSharpCreasesHaveNoSuchLine) {
  // A plane with tilted normals: the rule's own line (sigma_f 8, tight sigma_g, 8 passes), whose
  // extra passes the judge saw as gains (11.7 deg in, 1.0 after eight).
  DataEstimate e = choice_with(10, true).estimate;
  e.curved_share = 0;
  e.crease_length = 0;
  const AutoChoice plane = choose_filter_params(e);
  ASSERT_TRUE(detail::independent_normal_errors(plane));
  EXPECT_FALSE(detail::on_independent_errors_line(plane, plane.params));
  EXPECT_EQ(detail::judged_pass_budget(plane.params, plane, kFits), detail::kJudgedPassBudget);
}

// Where the noise hides the features (over 3 spacings), the rule averages plainly (sigma_f 8.5
// spacings, the feature term off) for up to 14 passes; the judge runs as many as its fits vouch
// for: passes that together reach no more points than the fits hold (k passes reach k times one
// pass's pi (2 sigma_f)^2 spacings^2), one at least. Under that noise the budget is whole.
TEST(JudgedPassBudget, WhereTheNoiseHidesTheFeaturesThePassesTheJudgesFitsHold) {
  DataEstimate e = choice_with(10, false).estimate;
  e.position_noise = 4 * e.area_spacing;
  const AutoChoice noisy = choose_filter_params(e);
  ASSERT_TRUE(detail::noise_hides_features(noisy.estimate));
  ASSERT_TRUE(detail::feature_term_off(noisy.params));
  ASSERT_EQ(noisy.params.iterations, 14);
  // sigma_f 8.5 spacings, reach 17 spacings: 907.9 points a pass.
  const double reach = 3.14159265358979 * 17 * 17;
  EXPECT_EQ(detail::judged_pass_budget(noisy.params, noisy, 4097), int(4097 / reach));  // 4
  EXPECT_EQ(detail::judged_pass_budget(noisy.params, noisy, 1025), 1);
  EXPECT_EQ(detail::judged_pass_budget(noisy.params, noisy, 257), 1) << "one pass at least";
  EXPECT_EQ(detail::judged_pass_budget(noisy.params, noisy, 100000), 14) << "no more than the setting's own";
  e.position_noise = 2 * e.area_spacing;
  const AutoChoice under = choose_filter_params(e);
  ASSERT_FALSE(detail::noise_hides_features(under.estimate));
  EXPECT_EQ(detail::judged_pass_budget(noisy.params, under, 1025), 14) << "the features seen: the whole budget";
  // The judged text says where the rule's "up to 14 passes" were held to fewer, and only there.
  EXPECT_EQ(detail::judged_budget_note(noisy.params, 4),
            " (its 14 passes held to 4, as many as the judge's fits reach)");
  EXPECT_EQ(detail::judged_budget_note(noisy.params, 14), "");
  ASSERT_LE(under.params.iterations, 8);
  EXPECT_EQ(detail::judged_budget_note(under.params, 8), "") << "a budget at or above the rule's passes";
}

// The judge's second setting for clean positions (smooth_detail_setting): tried beside the rule's
// where the judge chooses its scale (clean positions, Stein's estimate not deciding), with the
// whole budget; not on noisy positions, where the judge's fits hold the noise the passes share.
TEST(JudgedCandidates, SmoothDetailSettingOnCleanPositionsOnly) {
  DataEstimate e = choice_with(10, false).estimate;
  e.position_noise = 0;
  const AutoChoice clean = choose_filter_params(e);
  ASSERT_TRUE(detail::judge_chooses_scale(clean));
  const std::vector<FilterParams> judged = detail::judged_candidates(clean);
  ASSERT_EQ(judged.size(), 2u);
  EXPECT_EQ(judged[0].sigma_f, clean.params.sigma_f);
  EXPECT_EQ(judged[1].sigma_f, FilterParams().sigma_f / 2);
  EXPECT_EQ(judged[1].sigma_g, FilterParams().sigma_g);
  EXPECT_EQ(judged[1].units, Units::radius);
  EXPECT_EQ(detail::judged_pass_budget(judged[1], clean, kFits), detail::kJudgedPassBudget);

  const AutoChoice noisy = choice_with(10, false);
  EXPECT_FALSE(detail::judge_chooses_scale(noisy));
  EXPECT_EQ(detail::judged_candidates(noisy).size(), 1u);
}

// judged_passes_end, on judged RMS sequences from the real meshes (docs/auto.md, 100k points).
TEST(JudgedPassesEnd, TwoPassesPastTheBest) {
  // The casting, clean, PCA-16: best at pass 3 (3.23), two above it.
  EXPECT_FALSE(detail::judged_passes_end({4.49, 3.81, 3.37, 3.23, 3.31}, 3, 3.23, 8));
  EXPECT_TRUE(detail::judged_passes_end({4.49, 3.81, 3.37, 3.23, 3.31, 3.42}, 3, 3.23, 8));
}

TEST(JudgedPassesEnd, WhenShrinkingGainsCannotReachTheBar) {
  // The camel at 0.6% noise with tilted normals: 20.3 in, to beat 7.31. After pass 2 the larger
  // of the last two gains (4.1) could still carry six passes there; after pass 3 (gains 0.6 and
  // 0.04) five more reach 12.56 at best.
  EXPECT_FALSE(detail::judged_passes_end({20.3, 16.2}, 1, 7.31, 8)) << "one gain tells no trend";
  EXPECT_FALSE(detail::judged_passes_end({20.3, 16.2, 15.6}, 2, 7.31, 8));
  EXPECT_TRUE(detail::judged_passes_end({20.3, 16.2, 15.6, 15.56}, 3, 7.31, 8));
  // The same scores with a bar within their reach: go on.
  EXPECT_FALSE(detail::judged_passes_end({20.3, 16.2, 15.6, 15.56}, 3, 13.0, 8));
}

TEST(JudgedPassesEnd, NotOnGainsThatWaver) {
  // The held-out Armadillo at 0.6% noise with PCA-16 normals: 35.5 in, to beat 18.4; gains 2.0,
  // 2.0, 2.6, 2.7, 2.1, 1.9, then 2.1 twice, and pass 8 (18.0) passed the bar. Reaching on the last
  // gain alone (1.9) gave up after pass 6 at 22.2 - 2 x 1.9 = 18.4; the larger of the last two
  // (2.1) goes on.
  EXPECT_FALSE(detail::judged_passes_end({35.5, 33.5, 31.5, 28.9, 26.2, 24.1, 22.2}, 6, 18.4, 8));
}

TEST(JudgedPassesEnd, NotWhileTheGainsGrow) {
  // The camel at 0.6% noise with PCA-16 normals: 40.1 in, to beat 17.5; the gains grow over the
  // first passes (3.8, 5.7, 6.8) before they shrink, and pass 5 passed the bar.
  EXPECT_FALSE(detail::judged_passes_end({40.1, 36.3, 30.6, 23.8}, 3, 17.5, 14));
  // A small first gain, a larger second: a linear reach from the first would have given up.
  EXPECT_FALSE(detail::judged_passes_end({40.1, 39.9, 38.0}, 2, 17.5, 8));
}

TEST(JudgedPassesEnd, NotWhileThePassesStillBeatTheBest) {
  // The teddy at 0.25% noise with PCA-16 normals, gains shrinking, each pass the best so far:
  // the score to beat is the last pass's own.
  EXPECT_FALSE(detail::judged_passes_end({28.4, 23.3, 18.4, 14.7, 12.5, 10.9, 10.0}, 6, 10.0, 8));
}

// Where Stein's estimate decides, the judge only vetoes its pass, at the whole neighbourhood:
// fitting the input at both scales to choose one would be spent for nothing.
TEST(JudgeChoosesScale, OnlyWhereTheJudgeDecides) {
  AutoChoice clean = choice_with(10, true);
  clean.estimate.position_noise = 0.0005;  // twice it is under 0.15 spacings: the quarter allowed
  ASSERT_TRUE(detail::judge_geometry(clean.estimate).quarter_allowed);
  ASSERT_TRUE(detail::independent_normal_errors(clean));
  clean.estimate.normal_noise_neighbours_deg = 0;  // the neighbours measured no noise: the judge decides
  ASSERT_FALSE(detail::stein_decides(clean));
  EXPECT_TRUE(detail::judge_chooses_scale(clean));
  clean.estimate.normal_noise_neighbours_deg = 10;
  ASSERT_TRUE(detail::stein_decides(clean));
  EXPECT_FALSE(detail::judge_chooses_scale(clean));
  AutoChoice noisy = choice_with(10, false);
  ASSERT_FALSE(detail::judge_geometry(noisy.estimate).quarter_allowed);
  EXPECT_FALSE(detail::judge_chooses_scale(noisy));
}

}  // namespace
}  // namespace pnf::test
