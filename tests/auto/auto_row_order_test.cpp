// --auto does not depend on the input's row order (issue 31): estimate_data samples along the
// Morton curve and takes each sample's neighbours in canonical order, the judge too, so a shuffled
// cloud gives the same estimate, the same choice and the same normals, permuted, bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include "crease_clouds.hpp"
#include "pnf/estimate_data.hpp"
#include "pnf/improve_normals_auto.hpp"
#include "test_backends.hpp"

namespace pnf::test {
namespace {

PointCloud permuted(const PointCloud& cloud, const std::vector<std::size_t>& permutation) {
  PointCloud out;
  for (const std::size_t i : permutation) {
    out.positions.push_back(cloud.positions[i]);
    out.normals.push_back(cloud.normals[i]);
  }
  return out;
}

std::vector<std::size_t> shuffled_rows(std::size_t n, unsigned seed) {
  std::vector<std::size_t> rows(n);
  std::iota(rows.begin(), rows.end(), std::size_t(0));
  std::shuffle(rows.begin(), rows.end(), std::mt19937(seed));
  return rows;
}

void expect_same_estimate(const DataEstimate& a, const DataEstimate& b) {
  EXPECT_EQ(a.samples, b.samples);
  EXPECT_EQ(a.mean_radius, b.mean_radius);
  EXPECT_EQ(a.area_spacing, b.area_spacing);
  EXPECT_EQ(a.position_noise, b.position_noise);
  EXPECT_EQ(a.normal_noise_deg, b.normal_noise_deg);
  EXPECT_EQ(a.fit_neighbours, b.fit_neighbours);
  EXPECT_EQ(a.feature_share, b.feature_share);
  EXPECT_EQ(a.crease_length, b.crease_length);
  EXPECT_EQ(a.crease_sharpness, b.crease_sharpness);
  EXPECT_EQ(a.edge_samples, b.edge_samples);
  EXPECT_EQ(a.normal_crease_length, b.normal_crease_length);
  EXPECT_EQ(a.curved_share, b.curved_share);
  EXPECT_EQ(a.normal_error_correlation, b.normal_error_correlation);
  EXPECT_EQ(a.normal_position_coupling, b.normal_position_coupling);
}

// A noisy 90-degree crease with PCA normals: the rule filters it, the judge runs its passes.
Crease noisy_crease() {
  Crease c = make_crease(90, 20000, 0.2, 41);
  c.cloud.normals = pca16_normals(c.cloud.positions, c.truth);
  return c;
}

TEST(AutoRowOrder, ShuffledRowsGiveTheSameEstimate) {
  const Crease c = noisy_crease();
  const DataEstimate whole = estimate_data(c.cloud);
  for (const unsigned seed : {1u, 2u}) {
    SCOPED_TRACE(seed);
    expect_same_estimate(whole, estimate_data(permuted(c.cloud, shuffled_rows(c.cloud.size(), seed))));
  }
}

TEST(AutoRowOrder, ShuffledRowsGiveTheSameChoiceAndNormalsPermuted) {
  const Crease c = noisy_crease();
  NormalFilter& filter = *reference_filter();
  std::vector<Vec3> out(c.cloud.size());
  const AutoRun run = improve_normals_auto(CloudView(c.cloud), MutableVec3ArrayView(out), filter);
  ASSERT_GT(run.passes_kept, 0) << run.choice.rule << "\n" << run.choice.judged;  // the judge had passes to tell
  const std::vector<std::size_t> rows = shuffled_rows(c.cloud.size(), 3);
  const PointCloud shuffled = permuted(c.cloud, rows);
  std::vector<Vec3> out_shuffled(shuffled.size());
  const AutoRun again = improve_normals_auto(CloudView(shuffled), MutableVec3ArrayView(out_shuffled), filter);
  EXPECT_EQ(again.choice.rule, run.choice.rule);
  EXPECT_EQ(again.choice.judged, run.choice.judged);
  EXPECT_EQ(again.judged_rms_deg, run.judged_rms_deg);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    ASSERT_EQ(out_shuffled[k], out[rows[k]]) << "row " << k << " (input row " << rows[k] << ")";
  }
}

}  // namespace
}  // namespace pnf::test
