// `--auto` (pnf::improve_normals_auto) on the team's real meshes (../shared/data; skipped with a
// message where absent), sampled as pnf_eval_real samples them: cases where it once returned
// normals worse than its input (docs/auto.md) must come back no worse.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "auto/judged_passes.hpp"
#include "crease_clouds.hpp"
#include "eval_clouds.hpp"
#include "pnf/improve_normals_auto.hpp"
#include "real_meshes.hpp"
#include "test_clouds.hpp"

namespace pnf::test {
namespace {

std::string mesh_path(const std::string& name) { return shared_data_dir() + "/meshes/" + name + ".off"; }
std::string absent(const std::string& name) {
  return mesh_path(name) + " is absent (the team's ../shared/data; set PNF_SHARED_DATA)";
}

// `points` points (100k unless said) sampled on the team's mesh `name`, scaled to a unit
// diagonal, with their true normals, as pnf_eval_real samples them; none where the team's data
// is absent.
std::optional<eval::MeshSamples> sampled_mesh(const std::string& name, std::uint64_t seed,
                                              std::size_t points = 100000) {
  const std::string path = mesh_path(name);
  if (shared_data_dir().empty() || !std::ifstream(path)) return std::nullopt;
  eval::Mesh mesh = eval::read_mesh(path);
  eval::normalize_to_unit_diagonal(mesh);
  return eval::sample_mesh(mesh, eval::mesh_normals(mesh), points, seed);
}

// --auto on `cloud`, with its input's and its output's error from `truth`.
struct AutoOutcome {
  AutoRun run;
  eval::AngleError input, output;
};
AutoOutcome auto_outcome(const PointCloud& cloud, const std::vector<Vec3>& truth) {
  std::vector<Vec3> out(cloud.size());
  AutoOutcome o;
  o.run = improve_normals_auto(cloud, MutableVec3ArrayView(out), fastest_filter());
  o.input = eval::oriented_angle_error(cloud.normals, truth);
  o.output = eval::oriented_angle_error(out, truth);
  return o;
}

// --auto on `name`'s clean samples with PCA normals over 64 points; none where the data is absent.
std::optional<AutoOutcome> auto_on_clean_pca64(const std::string& name, std::uint64_t seed) {
  const std::optional<eval::MeshSamples> samples = sampled_mesh(name, seed);
  if (!samples) return std::nullopt;
  PointCloud cloud;
  cloud.positions = samples->shape.positions;
  cloud.normals = eval::pca_normals(cloud.positions, samples->shape.normals, 64);
  return auto_outcome(cloud, samples->shape.normals);
}

// --auto on `points` samples of `name` with position noise `noise` (of the diagonal, per axis;
// seeded `seed` + 1) and their exact normals (the truth: input error 0); none where the data is
// absent.
std::optional<AutoOutcome> auto_on_exact(const std::string& name, std::uint64_t seed, std::size_t points,
                                         double noise = 0) {
  const std::optional<eval::MeshSamples> samples = sampled_mesh(name, seed, points);
  if (!samples) return std::nullopt;
  PointCloud cloud;
  cloud.positions = samples->shape.positions;
  if (noise > 0) eval::add_noise(cloud.positions, noise, seed + 1);
  cloud.normals = samples->shape.normals;
  const AutoOutcome o = auto_outcome(cloud, samples->shape.normals);
  EXPECT_LT(o.input.rms_deg, 1e-6) << "the exact normals are the truth";
  return o;
}

// --auto on `points` samples of `name` with position noise `noise` (seeded `seed` + 1) and PCA
// normals over `k` points; none where the data is absent.
std::optional<AutoOutcome> auto_on_noisy_pca(const std::string& name, std::uint64_t seed, std::size_t points,
                                             double noise, int k) {
  const std::optional<eval::MeshSamples> samples = sampled_mesh(name, seed, points);
  if (!samples) return std::nullopt;
  PointCloud cloud;
  cloud.positions = samples->shape.positions;
  eval::add_noise(cloud.positions, noise, seed + 1);
  cloud.normals = eval::pca_normals(cloud.positions, samples->shape.normals, k);
  return auto_outcome(cloud, samples->shape.normals);
}

// `o`'s output no worse than its input, in RMS and mean: kept input normals come back unit
// length, so their rounding is allowed.
void expect_no_worse(const AutoOutcome& o) {
  SCOPED_TRACE(o.run.choice.rule + "; " + o.run.choice.judged);
  EXPECT_LE(o.output.rms_deg, o.input.rms_deg + 1e-6);
  EXPECT_LE(o.output.mean_deg, o.input.mean_deg + 1e-6);
}

// The crank (a CAD part with thin webs and small holes), 100k samples, position noise 0.25% of
// the diagonal per axis (about half a spacing), the true normals tilted by 10 degrees RMS: the
// judge's fits of 257 points smoothed its detail as the filter did and agreed with every pass,
// and eight were kept (pnf_eval_real's seeds: 9.86 deg in, 21.80 out) before judged_pass_budget.
TEST(AutoOnRealMeshes, NoisyCrankWithTiltedNormalsIsNoWorse) {
  const std::optional<eval::MeshSamples> samples = sampled_mesh("crank", 21);
  if (!samples) GTEST_SKIP() << absent("crank");
  const eval::MeshSamples& s = *samples;
  PointCloud cloud;
  cloud.positions = s.shape.positions;
  eval::add_noise(cloud.positions, 0.0025, 22);
  cloud.normals = eval::jittered_normals(s.shape.normals, 10, 23);
  const AutoOutcome o = auto_outcome(cloud, s.shape.normals);
  SCOPED_TRACE(o.run.choice.rule + "; " + o.run.choice.judged);
  // Input normals kept come back unit length, so "no worse" allows their rounding (1e-9 deg); before
  // judged_pass_budget these seeds gave 21.7 deg RMS (12.3 mean) from 9.87 (8.79).
  EXPECT_LE(o.output.rms_deg, o.input.rms_deg + 1e-9);
  EXPECT_LE(o.output.mean_deg, o.input.mean_deg + 1e-9);
}

// The teddy, 100k samples at 0.6% of its diagonal of noise (2.5 spacings), PCA-64 normals: the
// judge keeps none of the rule's passes and the fallback's first (16.83 deg in, 12.98 out on
// pnf_eval_real's seeds); its fits hold 4097 points, eight passes' reach, and the fallback's
// further passes, judged (judged_passes.hpp, fallback_pass_budget), are true gains (10.42).
TEST(AutoOnRealMeshes, NoisyTeddyWithWidePcaNormalsGainsFromTheFallbacksPasses) {
  const std::optional<AutoOutcome> outcome = auto_on_noisy_pca("teddy", 71, 100000, 0.006, 64);
  if (!outcome) GTEST_SKIP() << absent("teddy");
  const AutoOutcome& o = *outcome;
  SCOPED_TRACE(o.run.choice.rule + "; " + o.run.choice.judged);
  ASSERT_NE(o.run.choice.judged.find("; fallback sigma_f 4"), std::string::npos);
  EXPECT_GT(o.run.passes_kept, 1);
  EXPECT_LT(o.output.rms_deg, 0.7 * o.input.rms_deg);
  EXPECT_LT(o.output.mean_deg, 0.7 * o.input.mean_deg);
}

// The crank, 20k samples at 0.25% noise, PCA-16 normals: the judge's fits of 257 points hold one
// or two passes' reach, and further fallback passes there scored gains that were not (pnf_eval_real's
// seeds: 26.28 deg in, 25.98 after the fallback's first pass, 26.58 after three): one pass only.
TEST(AutoOnRealMeshes, SparseNoisyCrankWithPcaNormalsIsNoWorse) {
  const std::optional<AutoOutcome> outcome = auto_on_noisy_pca("crank", 73, 20000, 0.0025, 16);
  if (!outcome) GTEST_SKIP() << absent("crank");
  expect_no_worse(*outcome);
}

// The cup sampled at 10k points, clean positions, its exact normals: the nearest point of its
// other wall lies a few spacings away, inside the estimate's fits, whose gap the estimate read
// as 6.1 spacings of position noise when it fitted both walls; the rule then took its line for
// positions too noisy for features and the judge kept 7 passes of plain averaging (pnf_eval_real's
// seeds: 0 deg in, 29.4 out). Fitted to the sample's own sheet (sample_fit.cpp), the positions
// read as clean and the exact normals come back as they went in.
TEST(AutoOnRealMeshes, SparseCupWithExactNormalsIsNoWorse) {
  const std::optional<AutoOutcome> outcome = auto_on_exact("cup", 61, 10000);
  if (!outcome) GTEST_SKIP() << absent("cup");
  EXPECT_LT(outcome->run.choice.estimate.position_noise, 0.5 * outcome->run.choice.estimate.area_spacing);
  expect_no_worse(*outcome);
}

// The crank sampled at 10k points, clean positions, its exact normals: its thin webs and small
// holes are detail finer than the 16 points of the neighbours' noise fit, which read them as
// 21 deg of noise, and with that noise Stein's estimate kept passes (pnf_eval_real's seeds: 0 deg
// in, 7.63 out; these: 7.59). The chords to the nearest points read 0.26 deg there, and the input
// is kept.
TEST(AutoOnRealMeshes, SparseCrankWithExactNormalsIsNoWorse) {
  const std::optional<AutoOutcome> outcome = auto_on_exact("crank", 62, 10000);
  if (!outcome) GTEST_SKIP() << absent("crank");
  expect_no_worse(*outcome);
}

// The crank, 100k samples, position noise 0.25% of the diagonal per axis, its exact normals: the
// judge read them 17.4 deg from its fits with its own error at 2.4 deg and kept 8 passes
// (pnf_eval_real's seeds: 0 deg in, 19.1 out); their own noise reads 0.7 deg, under the judge's
// error, so no pass can be judged and the input is kept.
TEST(AutoOnRealMeshes, NoisyCrankWithExactNormalsIsNoWorse) {
  const std::optional<AutoOutcome> outcome = auto_on_exact("crank", 24, 100000, 0.0025);
  if (!outcome) GTEST_SKIP() << absent("crank");
  expect_no_worse(*outcome);
}

// The seahorse (fine fins and spines) sampled at 10k points, position noise 0.25% of the diagonal
// per axis (0.6 spacings), its exact normals: the judge's fits of 257 points miss the detail, and
// with its own error read at 7.7 deg it kept 8 passes (these seeds: 0 deg in, 24.3 out; read 25
// deg from its fits). The input's own noise (read 18.4 deg: the detail again) puts a floor of 17
// deg under the judge's error (judge_error_deg), and no pass beats the bars that sets.
TEST(AutoOnRealMeshes, SparseNoisySeahorseWithExactNormalsIsNoWorse) {
  const std::optional<AutoOutcome> outcome = auto_on_exact("seahorse2_100K", 26, 10000, 0.0025);
  if (!outcome) GTEST_SKIP() << absent("seahorse2_100K");
  expect_no_worse(*outcome);
}

// The seahorse sampled at 6k points, position noise 0.6% of the diagonal per axis, its exact
// normals: the estimate reads the noise as over 3 spacings, the judge fits 4097 of the 6000 points,
// and its fits, which follow the whole model's shape, scored 14 passes of wide averaging as gains
// (pnf_eval_real's seeds: 0 deg in, 47.4 out). Fits that hold more than half the cloud vouch for no
// pass (judge_fits_too_wide): the input is kept.
TEST(AutoOnRealMeshes, SparseSeahorseAtWideNoiseWithExactNormalsIsNoWorse) {
  const std::optional<AutoOutcome> outcome = auto_on_exact("seahorse2_100K", 28, 6000, 0.006);
  if (!outcome) GTEST_SKIP() << absent("seahorse2_100K");
  expect_no_worse(*outcome);
}

// The cup (thin walls) sampled at 20k points, position noise 0.6% of the diagonal per axis, PCA-16
// normals: the estimate reads the noise as over 3 spacings (too noisy for features) and the judge,
// fitting 4097 points, kept passes of plain averaging far beyond its fits' reach, which smoothed
// the walls' detail as its fits did (pnf_eval_real's seeds: 22.18 deg in, 25.86 out). Held to the
// passes its fits vouch for (judged_pass_budget), the output is no worse.
TEST(AutoOnRealMeshes, SparseNoisyCupWithPcaNormalsIsNoWorse) {
  const std::optional<AutoOutcome> outcome = auto_on_noisy_pca("cup", 51, 20000, 0.006, 16);
  if (!outcome) GTEST_SKIP() << absent("cup");
  expect_no_worse(*outcome);
}

// The camel (an organic shape with fine, smooth detail), 100k clean samples, PCA normals over 64
// points: the rule reads the detail as edges and its tight sigma_g's first pass was judged worse
// than the input, which was kept (pnf_eval_real: 6.97 deg); the judge's second setting for clean
// positions (smooth_detail_setting) gains and is kept, truly better than the input.
TEST(AutoOnRealMeshes, CleanCamelWithWidePcaNormalsGainsFromTheSmoothDetailSetting) {
  const std::optional<AutoOutcome> outcome = auto_on_clean_pca64("camel", 31);
  if (!outcome) GTEST_SKIP() << absent("camel");
  const AutoOutcome& o = *outcome;
  SCOPED_TRACE(o.run.choice.rule + "; " + o.run.choice.judged);
  const FilterParams smooth = detail::smooth_detail_setting(o.run.choice);
  EXPECT_EQ(o.run.choice.params.sigma_f, smooth.sigma_f);
  EXPECT_EQ(o.run.choice.params.sigma_g, smooth.sigma_g);
  EXPECT_GT(o.run.passes_kept, 0);
  EXPECT_LT(o.output.rms_deg, 0.95 * o.input.rms_deg);
  EXPECT_LT(o.output.mean_deg, o.input.mean_deg);
}

// The teddy (an organic shape with soft folds), 100k clean samples, PCA normals over 64 points:
// the judge fitted the nearest 64 points, each input normal's own, shared their smoothing and read
// the input at 0.98 deg (truly 1.37) with its own error at 0.71, so no pass could beat its bar and
// the input was kept (pnf_eval_real's seeds). Fitting half the 64 that the input follows, it reads
// the input at 1.21 deg, its own error at 0.22, and keeps a pass that truly gains (0.96 deg).
TEST(AutoOnRealMeshes, CleanTeddyWithWidePcaNormalsIsJudgedUnderTheirSupport) {
  const std::optional<AutoOutcome> outcome = auto_on_clean_pca64("teddy", 41);
  if (!outcome) GTEST_SKIP() << absent("teddy");
  const AutoOutcome& o = *outcome;
  SCOPED_TRACE(o.run.choice.rule + "; " + o.run.choice.judged);
  EXPECT_NE(o.run.choice.judged.find("fits of 32 points, under the 64 whose plane the input follows"),
            std::string::npos);
  EXPECT_GT(o.run.passes_kept, 0);
  EXPECT_LT(o.output.rms_deg, 0.9 * o.input.rms_deg);
  EXPECT_LT(o.output.mean_deg, o.input.mean_deg);
}

// The camel, 100k clean samples: with PCA normals over 16 points the judged settings' passes
// read no better than the input, which was kept (pnf_eval_real: 5.50 deg, where one pass of the
// narrow setting gives 5.05); as plane fits of 16 points they get the narrow pass, truly better.
// The same samples with their exact normals, which the judge reads as it reads the PCA ones, are
// no count's plane fits and come back as they were.
TEST(AutoOnRealMeshes, CleanCamelGetsTheNarrowPassForPcaNormalsOnly) {
  const std::optional<eval::MeshSamples> samples = sampled_mesh("camel", 51);
  if (!samples) GTEST_SKIP() << absent("camel");
  PointCloud cloud;
  cloud.positions = samples->shape.positions;
  cloud.normals = eval::pca_normals(cloud.positions, samples->shape.normals, 16);
  const AutoOutcome pca = auto_outcome(cloud, samples->shape.normals);
  SCOPED_TRACE(pca.run.choice.rule + "; " + pca.run.choice.judged);
  EXPECT_NE(pca.run.choice.judged.find("plane fits of 16 points: narrow pass"), std::string::npos);
  EXPECT_NE(pca.run.choice.judged.find(": the narrow pass, 1 pass kept"), std::string::npos);
  EXPECT_LT(pca.output.rms_deg, 0.95 * pca.input.rms_deg);
  EXPECT_LT(pca.output.mean_deg, pca.input.mean_deg);

  cloud.normals = samples->shape.normals;
  const AutoOutcome exact = auto_outcome(cloud, samples->shape.normals);
  SCOPED_TRACE(exact.run.choice.rule + "; " + exact.run.choice.judged);
  EXPECT_EQ(exact.run.choice.judged.find("plane fits"), std::string::npos);
  EXPECT_EQ(exact.run.passes_kept, 0);
  EXPECT_LE(exact.output.rms_deg, 1e-6);  // unit rows of the exact normals
}

}  // namespace
}  // namespace pnf::test
