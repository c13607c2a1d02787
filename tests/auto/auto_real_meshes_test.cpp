// `--auto` (pnf::improve_normals_auto) on the team's real meshes (../shared/data; skipped with a
// message where absent), sampled as pnf_eval_real samples them: cases where it once returned
// normals worse than its input (docs/auto.md) must come back no worse.
#include <gtest/gtest.h>

#include <fstream>
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

// The crank (a CAD part with thin webs and small holes), 100k samples, position noise 0.25% of
// the diagonal per axis (about half a spacing), the true normals tilted by 10 degrees RMS: the
// judge's fits of 257 points smoothed its detail as the filter did and agreed with every pass,
// and eight were kept (pnf_eval_real's seeds: 9.86 deg in, 21.80 out) before judged_pass_budget.
TEST(AutoOnRealMeshes, NoisyCrankWithTiltedNormalsIsNoWorse) {
  const std::string path = shared_data_dir() + "/meshes/crank.off";
  if (shared_data_dir().empty() || !std::ifstream(path)) {
    GTEST_SKIP() << path << " is absent (the team's ../shared/data; set PNF_SHARED_DATA)";
  }
  eval::Mesh mesh = eval::read_mesh(path);
  eval::normalize_to_unit_diagonal(mesh);
  const eval::MeshSamples s = eval::sample_mesh(mesh, eval::mesh_normals(mesh), 100000, 21);
  PointCloud cloud;
  cloud.positions = s.shape.positions;
  eval::add_noise(cloud.positions, 0.0025, 22);
  cloud.normals = eval::jittered_normals(s.shape.normals, 10, 23);
  const eval::AngleError input = eval::oriented_angle_error(cloud.normals, s.shape.normals);
  std::vector<Vec3> out(cloud.size());
  const AutoRun run = improve_normals_auto(cloud, MutableVec3ArrayView(out), fastest_filter());
  const eval::AngleError output = eval::oriented_angle_error(out, s.shape.normals);
  SCOPED_TRACE(run.choice.rule + "; " + run.choice.judged);
  // Input normals kept come back unit length, so "no worse" allows their rounding (1e-9 deg); before
  // judged_pass_budget these seeds gave 21.7 deg RMS (12.3 mean) from 9.87 (8.79).
  EXPECT_LE(output.rms_deg, input.rms_deg + 1e-9);
  EXPECT_LE(output.mean_deg, input.mean_deg + 1e-9);
}

// The camel (an organic shape with fine, smooth detail), 100k clean samples, PCA normals over 64
// points: the rule reads the detail as edges and its tight sigma_g's first pass was judged worse
// than the input, which was kept (pnf_eval_real: 6.97 deg); the judge's second setting for clean
// positions (smooth_detail_setting) gains and is kept, truly better than the input.
TEST(AutoOnRealMeshes, CleanCamelWithWidePcaNormalsGainsFromTheSmoothDetailSetting) {
  const std::string path = shared_data_dir() + "/meshes/camel.off";
  if (shared_data_dir().empty() || !std::ifstream(path)) {
    GTEST_SKIP() << path << " is absent (the team's ../shared/data; set PNF_SHARED_DATA)";
  }
  eval::Mesh mesh = eval::read_mesh(path);
  eval::normalize_to_unit_diagonal(mesh);
  const eval::MeshSamples s = eval::sample_mesh(mesh, eval::mesh_normals(mesh), 100000, 31);
  PointCloud cloud;
  cloud.positions = s.shape.positions;
  cloud.normals = eval::pca_normals(cloud.positions, s.shape.normals, 64);
  const eval::AngleError input = eval::oriented_angle_error(cloud.normals, s.shape.normals);
  std::vector<Vec3> out(cloud.size());
  const AutoRun run = improve_normals_auto(cloud, MutableVec3ArrayView(out), fastest_filter());
  const eval::AngleError output = eval::oriented_angle_error(out, s.shape.normals);
  SCOPED_TRACE(run.choice.rule + "; " + run.choice.judged);
  const FilterParams smooth = detail::smooth_detail_setting(run.choice);
  EXPECT_EQ(run.choice.params.sigma_f, smooth.sigma_f);
  EXPECT_EQ(run.choice.params.sigma_g, smooth.sigma_g);
  EXPECT_GT(run.passes_kept, 0);
  EXPECT_LT(output.rms_deg, 0.95 * input.rms_deg);
  EXPECT_LT(output.mean_deg, input.mean_deg);
}

}  // namespace
}  // namespace pnf::test
