// NormalFilter::run_observed (pnf/normal_filter.hpp): the observer sees each pass's normals in the
// cloud's row order, and ending the passes there leaves that pass's result, bit for bit as a
// plain run of that many passes gives it. run_observed_after_twin: two sets of normals over one
// build of the lists, each as its own run gives it, taking turns pass by pass over whole lists.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "pnf/angle.hpp"
#include "pnf/error.hpp"
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
  const pnf::FilterSummary summary = filter->run_observed(pnf::CloudView(ball), pnf::MutableVec3ArrayView(out), params,
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

// The twin's normals: the cloud's, each turned by a few degrees in its own direction.
std::vector<Vec3> tilted(const std::vector<Vec3>& normals) {
  std::vector<Vec3> out(normals.size());
  for (std::size_t i = 0; i < normals.size(); ++i) {
    const double t = double(i);
    out[i] = {normals[i][0] + 0.1 * std::sin(t), normals[i][1] + 0.1 * std::cos(3 * t),
              normals[i][2] + 0.1 * std::sin(7 * t)};
  }
  return out;
}

// Each pass's normals a run_observed of `params` on `cloud` shows, ended after `passes`.
std::vector<std::vector<double>> observed_alone(NormalFilter& filter, const pnf::CloudView& cloud,
                                                const FilterParams& params, int passes) {
  std::vector<std::vector<double>> seen;
  std::vector<Vec3> out(cloud.size());
  filter.run_observed(cloud, pnf::MutableVec3ArrayView(out), params, [&](int pass, const std::vector<double>& n) {
    seen.push_back(n);
    return pass < passes;
  });
  return seen;
}

// The twin run shares the lists with the cloud's run; each set's passes are the bits its own run
// gives (the positions are distinct, so the twin's order is its own run's too), whether the lists
// stay on the device (one chunk) or are refilled chunk by chunk. The twin may end its passes
// early without ending the cloud's.
void expect_twin_as_two_runs(NormalFilter& filter) {
  const PointCloud ball = sphere(3000, 2.0, 31);
  const std::vector<Vec3> twin = tilted(ball.normals);
  FilterParams params;
  params.iterations = 3;
  std::vector<std::vector<double>> seen_twin, seen;
  std::vector<Vec3> out(ball.size());
  const pnf::FilterSummary summary = filter.run_observed_after_twin(
      pnf::CloudView(ball), twin,
      [&](int pass, const std::vector<double>& n) {
        seen_twin.push_back(n);
        return pass < 2;
      },
      pnf::MutableVec3ArrayView(out), params,
      [&](int, const std::vector<double>& n) {
        seen.push_back(n);
        return true;
      });
  EXPECT_EQ(summary.passes_run, 3);
  EXPECT_EQ(seen_twin, observed_alone(filter, pnf::CloudView(ball.positions, twin), params, 2));
  EXPECT_EQ(seen, observed_alone(filter, pnf::CloudView(ball), params, 3));
  EXPECT_EQ(out, filter.run(ball, params).normals);
}

TEST_P(RunObservedTest, TwinRunGivesEachSetTheBitsOfItsOwnRun) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(GetParam());
  PNF_SKIP_IF_NULL(filter);
  expect_twin_as_two_runs(*filter);
}

TEST(RunObserved, TwinRunOverChunkedListsGivesEachSetTheBitsOfItsOwnRun) {
  pnf::FilterOptions options{pnf::Device::reference()};
  options.memory.budget_bytes = 200 * 1024;  // a tenth or so of this cloud's lists
  NormalFilter chunked(options);
  expect_twin_as_two_runs(chunked);
}

// How many passes the twin runs when the cloud's observer ends the cloud's run after 2 of 6.
int twin_passes_when_the_cloud_ends_after_two(NormalFilter& filter) {
  const PointCloud ball = sphere(3000, 2.0, 31);
  FilterParams params;
  params.iterations = 6;
  int twin_passes = 0;
  std::vector<Vec3> out(ball.size());
  const pnf::FilterSummary summary = filter.run_observed_after_twin(
      pnf::CloudView(ball), tilted(ball.normals),
      [&](int, const std::vector<double>&) {
        ++twin_passes;
        return true;
      },
      pnf::MutableVec3ArrayView(out), params, [&](int pass, const std::vector<double>&) { return pass < 2; });
  EXPECT_EQ(summary.passes_run, 2);
  return twin_passes;
}

// Where the lists stay whole on the device, the two runs take turns pass by pass, so the twin
// runs no pass past the cloud's last (it ran its whole budget first before); over chunked lists,
// which each turn would fill again, the twin's passes still all run first.
TEST_P(RunObservedTest, TwinRunsNoPassPastTheCloudsLastOverWholeLists) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(GetParam());
  PNF_SKIP_IF_NULL(filter);
  EXPECT_EQ(twin_passes_when_the_cloud_ends_after_two(*filter), 2);
}

TEST(RunObserved, TwinRunsItsWholeBudgetFirstOverChunkedLists) {
  pnf::FilterOptions options{pnf::Device::reference()};
  options.memory.budget_bytes = 200 * 1024;
  NormalFilter chunked(options);
  EXPECT_EQ(twin_passes_when_the_cloud_ends_after_two(chunked), 6);
}

TEST(RunObserved, TwinWithAZeroNormalIsRefusedNamingIt) {
  const PointCloud ball = sphere(500, 2.0, 31);
  std::vector<Vec3> twin = ball.normals;
  twin[17] = {0, 0, 0};
  std::vector<Vec3> out(ball.size());
  try {
    pnf::test::reference_filter()->run_observed_after_twin(pnf::CloudView(ball), twin, {},
                                                           pnf::MutableVec3ArrayView(out), {}, {});
    FAIL() << "no error";
  } catch (const pnf::Error& e) {
    EXPECT_EQ(e.code(), pnf::ErrorCode::invalid_input);
    const std::string what = e.what();
    EXPECT_NE(what.find("the twin run"), std::string::npos) << what;
    EXPECT_NE(what.find("17"), std::string::npos) << what;
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, RunObservedTest, ::testing::Values(Backend::reference, Backend::opencl),
                         [](const auto& info) { return std::string(pnf::to_string(info.param)); });

}  // namespace
