// NormalFilter::run_observed (pnf/normal_filter.hpp): the observer sees each pass's normals in the
// cloud's row order, and ending the passes there leaves that pass's result, bit for bit as a
// plain run of that many passes gives it.
#include <gtest/gtest.h>

#include <vector>

#include "pnf/angle.hpp"
#include "pnf/normal_filter.hpp"
#include "test_backends.hpp"
#include "test_clouds.hpp"

namespace {

using pnf::Backend;
using pnf::FilterParams;
using pnf::NormalFilter;
using pnf::PointCloud;
using pnf::Vec3;
using namespace pnf::test;

class RunObservedTest : public ::testing::TestWithParam<Backend> {};

TEST_P(RunObservedTest, ObserverSeesEachPassAndCanEndThePasses) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(GetParam());
  PNF_SKIP_IF_NULL(filter);
  PointCloud ball = sphere(3000, 2.0, 31);
  FilterParams params;
  params.iterations = 5;
  std::vector<std::vector<double>> seen;
  std::vector<Vec3> out(ball.size());
  const pnf::FilterSummary summary = filter->run_observed(
      pnf::CloudView(ball), pnf::MutableVec3ArrayView(out), params,
      [&](int pass, const std::vector<double>& normals) {
        EXPECT_EQ(pass, int(seen.size()) + 1);
        seen.push_back(normals);
        return pass < 2;  // end after the second pass
      });
  EXPECT_EQ(summary.passes_run, 2);
  ASSERT_EQ(seen.size(), 2u);
  // Plain runs of one and two passes, in row order: normals_out is re-normalised in double at the
  // end of a run, the observer sees the passes' own rows, unit to rounding (1e-12 degrees).
  for (int passes : {1, 2}) {
    params.iterations = passes;
    const std::vector<Vec3> plain = filter->run(ball, params).normals;
    const std::vector<double>& observed = seen[std::size_t(passes - 1)];
    ASSERT_EQ(observed.size(), 3 * plain.size());
    for (std::size_t i = 0; i < plain.size(); ++i) {
      const Vec3 n{observed[3 * i], observed[3 * i + 1], observed[3 * i + 2]};
      ASSERT_LT(pnf::angle_degrees(n, plain[i]), 1e-12) << passes << " " << i;
    }
    if (passes == 2) EXPECT_EQ(out, plain);
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, RunObservedTest, ::testing::Values(Backend::reference, Backend::opencl),
                         [](const auto& info) { return std::string(pnf::to_string(info.param)); });

}  // namespace
