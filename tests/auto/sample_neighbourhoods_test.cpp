// --auto's samples and their neighbourhoods (lib/src/auto/sample_neighbourhoods.hpp), shared by
// the estimate's fits and the judge: checked against a brute-force search.
#include "auto/sample_neighbourhoods.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "pnf/error.hpp"
#include "spatial/spatial_index.hpp"
#include "spatial/spatial_order.hpp"
#include "test_clouds.hpp"

namespace pnf::test {
namespace {

double squared_distance(const Vec3& a, const Vec3& b) {
  return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
}

TEST(SampleNeighbourhoods, AreEachSamplesNearestPointsNearestFirst) {
  const PointCloud s = sphere(3000, 1.0, 11);
  const detail::SpatialIndex index(xyz_rows(s.positions), detail::SpatialIndex::Layout::any_order);
  const std::vector<std::uint32_t> curve = detail::morton_order(Vec3ArrayView(s.positions));
  const int k = 40;
  const detail::SampleNeighbourhoods n =
      detail::sample_neighbourhoods(index, curve, detail::ranks_of(curve), 300, k, {}, "test");
  ASSERT_EQ(n.samples(), 300u);
  ASSERT_EQ(n.neighbours, k);
  for (std::size_t sample = 0; sample < n.samples(); ++sample) {
    const std::size_t self = n.selves[sample];
    EXPECT_EQ(self, curve[sample * s.size() / 300]) << "sample " << sample << " along the curve";
    std::vector<double> all;
    for (const Vec3& p : s.positions) all.push_back(squared_distance(p, s.positions[self]));
    std::sort(all.begin(), all.end());
    for (int j = 0; j < k; ++j) {
      const std::size_t id = n.ids_of(sample)[j];
      const double d = n.squared_distances_of(sample)[j];
      EXPECT_DOUBLE_EQ(d, squared_distance(s.positions[id], s.positions[self]));
      EXPECT_DOUBLE_EQ(d, all[std::size_t(j)])
          << "sample " << sample << ", neighbour " << j << " is not the " << j << "-th nearest";
    }
  }
}

TEST(SampleNeighbourhoods, NeverMoreSamplesThanPointsOrTheLookUpBudget) {
  EXPECT_EQ(detail::samples_at_scale(100, 65), 100u);
  EXPECT_EQ(detail::samples_at_scale(1000000, 65), detail::kMaxSamples);
  EXPECT_EQ(detail::samples_at_scale(1000000, 4097), detail::kMaxLookupsPerScale / 4097);
}

// Asked before the search and about every 0.1 s during it (a search of some seconds here, so
// the calling thread asks within it whatever the thread count: 4M look-ups, 64 MB); false stops it.
TEST(SampleNeighbourhoods, StopWhenThePollSaysSo) {
  const PointCloud s = sphere(200000, 1.0, 12);
  const detail::SpatialIndex index(xyz_rows(s.positions), detail::SpatialIndex::Layout::any_order);
  const std::vector<std::uint32_t> curve = detail::morton_order(Vec3ArrayView(s.positions));
  const std::vector<std::uint32_t> rank = detail::ranks_of(curve);
  for (int answer_false_at : {1, 2}) {
    int asked = 0;
    double last_fraction = -1;
    try {
      detail::sample_neighbourhoods(
          index, curve, rank, 2000, 2049,
          [&](double fraction) {
            last_fraction = fraction;
            return ++asked < answer_false_at;
          },
          "estimate_data");
      FAIL() << "no error, " << asked << " polls";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::cancelled);
      EXPECT_NE(std::string(e.what()).find("estimate_data"), std::string::npos) << e.what();
    }
    EXPECT_EQ(asked, answer_false_at);
    if (answer_false_at == 2) EXPECT_GT(last_fraction, 0) << "the second ask comes from within the search";
  }
}

}  // namespace
}  // namespace pnf::test
