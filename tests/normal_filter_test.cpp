// The filter's behaviour on both backends: the paper's sidebar cases, the invariants of docs/method.md, and
// bad input. Expected values come from the known geometry, never from a previous run.
#include "pnf/normal_filter.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <thread>
#include <utility>
#include <vector>

#include "test_backends.hpp"
#include "test_clouds.hpp"

namespace {

using pnf::Backend;
using pnf::FilterParams;
using pnf::NormalFilter;
using pnf::PointCloud;
using pnf::Vec3;
using namespace pnf::test;

class NormalFilterTest : public ::testing::TestWithParam<Backend> {};

std::vector<double> mean_error_per_pass(NormalFilter& filter, const PointCloud& cloud, const std::vector<Vec3>& truth,
                                        int passes) {
  std::vector<double> errors = {mean_angle_deg(cloud.normals, truth)};
  for (int k = 1; k <= passes; ++k) {
    FilterParams params;
    params.iterations = k;
    errors.push_back(mean_angle_deg(filter.run(cloud, params).normals, truth));
  }
  return errors;
}

TEST_P(NormalFilterTest, SidebarPlaneWithJitteredNormals) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(GetParam());
  PNF_SKIP_IF_NULL(filter);
  // Exact positions on z = 0 (jittered within the plane), normals turned by about 15 degrees.
  PointCloud plane = jittered_grid(50, 1.0, 0.2, 1);
  std::mt19937 rng(2);
  std::vector<Vec3> truth(plane.size(), Vec3{0, 0, 1});
  for (Vec3& n : plane.normals) n = jitter_normal(n, 15, rng);
  std::vector<double> e = mean_error_per_pass(*filter, plane, truth, 4);
  for (int k = 1; k <= 4; ++k) EXPECT_LT(e[k], e[k - 1]) << "pass " << k << " did not improve the normals";
  EXPECT_LT(e[4], e[0] / 10) << "input " << e[0] << " deg, after 4 passes " << e[4] << " deg";
}

TEST_P(NormalFilterTest, SidebarPlaneWithPositionNoiseStillImprovesEveryPass) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(GetParam());
  PNF_SKIP_IF_NULL(filter);
  PointCloud plane = jittered_grid(50, 1.0, 0.2, 3);
  std::mt19937 rng(4);
  std::normal_distribution<double> height(0, 0.05);  // 5% of the spacing along the normal
  for (Vec3& p : plane.positions) p[2] = height(rng);
  std::vector<Vec3> truth(plane.size(), Vec3{0, 0, 1});
  for (Vec3& n : plane.normals) n = jitter_normal(n, 15, rng);
  std::vector<double> e = mean_error_per_pass(*filter, plane, truth, 4);
  for (int k = 1; k <= 4; ++k) EXPECT_LT(e[k], e[k - 1]) << "pass " << k << " did not improve the normals";
}

TEST_P(NormalFilterTest, WedgeEdgeStaysFarSharperThanGaussianAveraging) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(GetParam());
  PNF_SKIP_IF_NULL(filter);
  const double h = 1.0;
  PointCloud ridge = wedge(20, 40, h, 0.2, 5);
  const std::vector<Vec3> truth = ridge.normals;
  std::mt19937 rng(6);
  std::normal_distribution<double> offset(0, 0.05 * h);  // position noise along the true normal
  for (std::size_t i = 0; i < ridge.size(); ++i) {
    double o = offset(rng);
    for (int k = 0; k < 3; ++k) ridge.positions[i][k] += o * truth[i][k];
    ridge.normals[i] = jitter_normal(truth[i], 10, rng);
  }
  FilterParams params;  // the paper's defaults, in mean radii (about h here)
  std::vector<Vec3> filtered = filter->run(ridge, params).normals;

  // Plain Gaussian averaging with the same spatial weight f and reach.
  const double sigma = params.sigma_f * h;
  double filter_error = 0, average_error = 0;
  int near_edge = 0;
  for (std::size_t i = 0; i < ridge.size(); ++i) {
    const Vec3& s = ridge.positions[i];
    double edge_distance = std::sqrt(s[0] * s[0] + s[2] * s[2]);
    if (edge_distance > 2 * h) continue;
    // Skip the open ends of the strip, where the neighbourhood is cut short along the edge.
    if (s[1] < 2 * sigma || s[1] > 39 * h - 2 * sigma) continue;
    Vec3 sum = {0, 0, 0};
    for (std::size_t j = 0; j < ridge.size(); ++j) {
      const Vec3& p = ridge.positions[j];
      double d2 = std::pow(p[0] - s[0], 2) + std::pow(p[1] - s[1], 2) + std::pow(p[2] - s[2], 2);
      if (d2 > 4 * sigma * sigma) continue;
      double w = std::exp(-d2 / (2 * sigma * sigma));
      for (int k = 0; k < 3; ++k) sum[k] += w * ridge.normals[j][k];
    }
    average_error += angle_deg(normalized(sum), truth[i]);
    filter_error += angle_deg(filtered[i], truth[i]);
    ++near_edge;
  }
  ASSERT_GT(near_edge, 50);
  filter_error /= near_edge;
  average_error /= near_edge;
  RecordProperty("filter_error_deg", std::to_string(filter_error));
  RecordProperty("average_error_deg", std::to_string(average_error));
  EXPECT_LT(filter_error, 0.2 * average_error)
      << "near the edge: filter " << filter_error << " deg, Gaussian averaging " << average_error << " deg";
}

TEST_P(NormalFilterTest, NoNormalIsFlippedAndPositionsAreUntouched) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(GetParam());
  PNF_SKIP_IF_NULL(filter);
  PointCloud ball = jittered_sphere(3000, 5.0, 7, 40);
  const PointCloud before = ball;
  std::vector<Vec3> out = filter->run(ball, FilterParams{}).normals;
  ASSERT_EQ(out.size(), ball.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    EXPECT_GT(dot(out[i], ball.normals[i]), 0) << "normal " << i << " turned to the other side";
    EXPECT_NEAR(norm(out[i]), 1.0, 1e-12) << "normal " << i;
  }
  ASSERT_EQ(std::memcmp(before.positions.data(), ball.positions.data(), ball.size() * sizeof(Vec3)), 0);
}

TEST_P(NormalFilterTest, TranslationByAMillionChangesNoNormal) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(GetParam());
  PNF_SKIP_IF_NULL(filter);
  PointCloud ball = jittered_sphere(3000, 5.0, 9, 15);
  PointCloud moved = ball;
  for (Vec3& p : moved.positions)
    for (double& v : p) v += 1e6;
  std::vector<Vec3> a = filter->run(ball).normals, b = filter->run(moved).normals;
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_LE(angle_deg(a[i], b[i]), 0.01) << "point " << i;
}

// One stray point far from the rest (a sensor's stray return, a (0,0,0) row in georeferenced
// data) moved the bounding box's centre, where positions were re-centred before becoming float,
// so far from the other points that their floats lost the spacing: the ball's normals came out
// degrees off with the point 1e6 away, and worse than their input 1e9 away. The origin is now
// the points' middle (docs/method.md, "Recentring"); the other normals are as without the point,
// to the translation test's 0.01 degrees (their origin moves by the median's shift of a sample).
TEST_P(NormalFilterTest, AFarPointLeavesTheOthersAsTheyWere) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(GetParam());
  PNF_SKIP_IF_NULL(filter);
  const PointCloud ball = jittered_sphere(3000, 5.0, 9, 15);
  const std::vector<Vec3> alone = filter->run(ball).normals;
  for (double far : {1e6, -1e9}) {
    PointCloud with_stray = ball;
    with_stray.positions.push_back({far, far / 2, 3});
    with_stray.normals.push_back({0, 0, 1});
    const std::vector<Vec3> out = filter->run(with_stray).normals;
    double worst = 0;
    for (std::size_t i = 0; i < alone.size(); ++i) worst = std::max(worst, angle_deg(alone[i], out[i]));
    EXPECT_LE(worst, 0.01) << "a point at " << far;
    EXPECT_LE(angle_deg(out.back(), {0, 0, 1}), 1e-6) << "the stray point has no neighbour: its normal stays";
  }
}

TEST_P(NormalFilterTest, RotatingTheInputRotatesTheOutput) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(GetParam());
  PNF_SKIP_IF_NULL(filter);
  PointCloud ball = jittered_sphere(2000, 5.0, 11, 15);
  const double a = 0.7, c = std::cos(a), s = std::sin(a);
  auto rotate = [&](const Vec3& v) { return Vec3{c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]}; };
  PointCloud turned = ball;
  for (std::size_t i = 0; i < ball.size(); ++i) {
    turned.positions[i] = rotate(ball.positions[i]);
    turned.normals[i] = rotate(ball.normals[i]);
  }
  std::vector<Vec3> out = filter->run(ball).normals, out_turned = filter->run(turned).normals;
  // float32 kernels see rotated coordinates rounded differently; 0.01 deg is the parity bar of docs/method.md.
  for (std::size_t i = 0; i < out.size(); ++i) EXPECT_LE(angle_deg(rotate(out[i]), out_turned[i]), 0.01) << i;
}

TEST_P(NormalFilterTest, ChunkedEqualsWhole) {
  if (GetParam() == Backend::opencl) {
    std::string why;
    if (!pnf::test::opencl_filter(why)) PNF_OPENCL_OR_SKIP(why);
  }
  PointCloud ball = jittered_sphere(4000, 5.0, 13, 20);
  pnf::FilterOptions whole_options{GetParam() == Backend::reference ? pnf::Device::reference() : pnf::Device::opencl()};
  pnf::FilterOptions chunked_options = whole_options;
  chunked_options.memory.budget_bytes = 200 * 1024;  // a tenth or so of this cloud's lists
  pnf::FilterResult whole = NormalFilter(whole_options).run(ball);
  pnf::FilterResult chunked = NormalFilter(chunked_options).run(ball);
  EXPECT_EQ(whole.summary.chunks, 1u);
  EXPECT_GT(chunked.summary.chunks, 3u);
  for (std::size_t i = 0; i < ball.size(); ++i) {
    // Same lists, same order, same arithmetic: bit-identical.
    EXPECT_EQ(whole.normals[i], chunked.normals[i]) << "point " << i;
  }
}

TEST_P(NormalFilterTest, ZeroIterationsReturnTheInputNormals) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(GetParam());
  PNF_SKIP_IF_NULL(filter);
  PointCloud ball = sphere(500, 2.0, 15);
  ball.normals[3] = {0, 0, 7};  // non-unit: comes back normalised
  FilterParams params;
  params.iterations = 0;
  std::vector<Vec3> out = filter->run(ball, params).normals;
  for (std::size_t i = 0; i < out.size(); ++i) {
    Vec3 expected = normalized(ball.normals[i]);
    for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(out[i][k], expected[k]) << "point " << i;
  }
}

TEST_P(NormalFilterTest, NonUnitNormalsActLikeTheirDirections) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(GetParam());
  PNF_SKIP_IF_NULL(filter);
  PointCloud ball = jittered_sphere(1500, 2.0, 16, 15);
  PointCloud scaled = ball;
  for (std::size_t i = 0; i < scaled.size(); ++i)
    for (double& v : scaled.normals[i]) v *= 1.0 + double(i % 7);
  std::vector<Vec3> a = filter->run(ball).normals, b = filter->run(scaled).normals;
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_LE(angle_deg(a[i], b[i]), 1e-4) << i;
}

TEST_P(NormalFilterTest, ProgressIsReportedPerPassAndCanCancel) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(GetParam());
  PNF_SKIP_IF_NULL(filter);
  PointCloud ball = sphere(500, 2.0, 18);
  FilterParams params;
  params.iterations = 3;
  std::vector<int> seen;
  std::vector<double> list_fractions;
  const std::thread::id caller = std::this_thread::get_id();
  filter->run(ball, params, [&](const pnf::PassProgress& p) {
    EXPECT_EQ(p.passes, 3);
    EXPECT_EQ(std::this_thread::get_id(), caller) << "reported from a worker thread";
    if (p.stage == pnf::ProgressStage::lists) {
      EXPECT_TRUE(seen.empty()) << "lists reported after a pass of an in-memory run";
      EXPECT_EQ(p.pass, 0);
      list_fractions.push_back(p.fraction);
    } else if (p.stage == pnf::ProgressStage::filtering) {
      EXPECT_EQ(p.pass, int(seen.size())) << "within a pass: the passes finished so far";
    } else {
      EXPECT_EQ(p.stage, pnf::ProgressStage::pass);
      EXPECT_EQ(p.fraction, 1.0);
      seen.push_back(p.pass);
    }
    return true;
  });
  EXPECT_EQ(seen, (std::vector<int>{1, 2, 3}));
  ASSERT_FALSE(list_fractions.empty());
  EXPECT_TRUE(std::is_sorted(list_fractions.begin(), list_fractions.end()));
  EXPECT_EQ(list_fractions.back(), 1.0);  // the build's end is always reported
  try {
    filter->run(ball, params, [](const pnf::PassProgress& p) { return p.pass < 2; });
    FAIL() << "not cancelled";
  } catch (const pnf::Error& e) {
    EXPECT_EQ(e.code(), pnf::ErrorCode::cancelled);
  }
  // Cancelled while the lists are built: no pass runs, the output is not written.
  std::vector<Vec3> out(ball.size(), Vec3{7, 7, 7});
  int passes_reported = 0;
  try {
    filter->run(pnf::CloudView(ball), pnf::MutableVec3ArrayView(out), params, [&](const pnf::PassProgress& p) {
      passes_reported += p.stage == pnf::ProgressStage::pass;
      return p.stage != pnf::ProgressStage::lists;
    });
    FAIL() << "not cancelled";
  } catch (const pnf::Error& e) {
    EXPECT_EQ(e.code(), pnf::ErrorCode::cancelled) << e.what();
  }
  EXPECT_EQ(passes_reported, 0);
  for (const Vec3& n : out) EXPECT_EQ(n, (Vec3{7, 7, 7}));
}

// A pass of more pairs than the engine's first slice (4M, filter_engine.cpp) runs in slices when
// a progress callback is given: reported as stage filtering, cancellable there, and giving the
// same normals, bit for bit, as a run without a callback (each point's update reads only the
// pass's input normals).
TEST_P(NormalFilterTest, PassesRunInSlicesThatReportAndCancel) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(GetParam());
  PNF_SKIP_IF_NULL(filter);
  PointCloud ball = sphere(80000, 2.0, 23);
  FilterParams params;
  params.iterations = 2;
  const pnf::FilterResult whole = filter->run(ball, params);
  ASSERT_GT(whole.summary.neighbour_pairs, std::size_t(6) << 20) << "too few pairs for two slices";
  std::vector<std::pair<int, double>> inside;  // (passes finished, fraction) within the passes
  const pnf::FilterResult sliced = filter->run(ball, params, [&](const pnf::PassProgress& p) {
    if (p.stage == pnf::ProgressStage::filtering) inside.emplace_back(p.pass, p.fraction);
    return true;
  });
  EXPECT_EQ(sliced.normals, whole.normals);
  // The first pass's first slice has 4M pairs, so that pass has two slices or more; later slices
  // follow the measured rate (kSliceSeconds), so the second pass may run in one.
  ASSERT_GE(inside.size(), 3u);
  EXPECT_TRUE(std::is_sorted(inside.begin(), inside.end()));
  EXPECT_EQ(inside.front().first, 0);
  EXPECT_LT(inside.front().second, 1.0);
  EXPECT_EQ(inside.back(), (std::pair<int, double>{1, 1.0}));
  // Cancelled at the first slice: no pass ends, and the error says where.
  int passes_reported = 0;
  try {
    filter->run(ball, params, [&](const pnf::PassProgress& p) {
      passes_reported += p.stage == pnf::ProgressStage::pass;
      return p.stage != pnf::ProgressStage::filtering;
    });
    FAIL() << "not cancelled";
  } catch (const pnf::Error& e) {
    EXPECT_EQ(e.code(), pnf::ErrorCode::cancelled) << e.what();
    EXPECT_NE(std::string(e.what()).find("during pass 1"), std::string::npos) << e.what();
  }
  EXPECT_EQ(passes_reported, 0);
}

TEST_P(NormalFilterTest, RadiusPropertyAndGivenRadiusSetTheScale) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(GetParam());
  PNF_SKIP_IF_NULL(filter);
  PointCloud grid = jittered_grid(20, 1.0, 0.1, 19);
  grid.radii.assign(grid.size(), 0.75);
  grid.radii[0] = 1.15;  // mean = 0.75 + 0.4 / 400 = 0.751
  pnf::FilterResult r = filter->run(grid);
  EXPECT_EQ(r.summary.radius_source, pnf::RadiusSource::property);
  EXPECT_DOUBLE_EQ(r.summary.mean_radius, 0.751);
  EXPECT_DOUBLE_EQ(r.summary.sigma_f, 4 * 0.751);
  FilterParams given;
  given.mean_radius = 2.0;
  r = filter->run(grid, given);
  EXPECT_EQ(r.summary.radius_source, pnf::RadiusSource::given);
  EXPECT_DOUBLE_EQ(r.summary.sigma_g, 1.0);
  grid.radii.clear();
  r = filter->run(grid);
  EXPECT_EQ(r.summary.radius_source, pnf::RadiusSource::estimate);
  EXPECT_NEAR(r.summary.mean_radius, 1.0, 0.25);
  FilterParams absolute;
  absolute.units = pnf::Units::absolute;
  r = filter->run(grid, absolute);
  EXPECT_DOUBLE_EQ(r.summary.sigma_f, 4.0);
  // Every grid point within 2 sigma_f = 8 of a centre point: (2*8+1)^2 minus the corners beyond 8.
  EXPECT_GT(r.summary.neighbours_max, 150u);
}

// Bad input: docs/method.md's result or a clear error that names the vertex.
std::string run_error(NormalFilter& filter, const PointCloud& cloud, const FilterParams& params = {}) {
  try {
    filter.run(cloud, params);
  } catch (const pnf::Error& e) {
    return std::string(pnf::to_string(e.code())) + ": " + e.what();
  }
  return "";
}

TEST_P(NormalFilterTest, BadInputIsAClearError) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(GetParam());
  PNF_SKIP_IF_NULL(filter);
  PointCloud ball = sphere(100, 1.0, 20);
  PointCloud nan_point = ball;
  nan_point.positions[42][1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(run_error(*filter, nan_point), "invalid_input: vertex 42 has a NaN or infinite coordinate");
  PointCloud inf_normal = ball;
  inf_normal.normals[7][0] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(run_error(*filter, inf_normal), "invalid_input: vertex 7 has a NaN or infinite normal component");
  PointCloud zero = ball;
  zero.normals[13] = {0, 0, 0};
  EXPECT_EQ(run_error(*filter, zero), "invalid_input: vertex 13 has a zero-length normal");
  // Finite, but not normalisable in double: it once came back NaN, unrefused.
  PointCloud huge = ball;
  huge.normals[21] = {1e200, 0, 1e200};
  EXPECT_EQ(run_error(*filter, huge),
            "invalid_input: vertex 21 has a normal too long to normalise in double (components from about 1e154); "
            "scale it");
  PointCloud tiny = ball;
  tiny.normals[22] = {1e-300, 1e-300, 1e-300};
  EXPECT_EQ(run_error(*filter, tiny),
            "invalid_input: vertex 22 has a zero-length normal (its components, under about 1e-154, square to 0 in "
            "double)");
  PointCloud no_normals = ball;
  no_normals.normals.clear();
  EXPECT_NE(run_error(*filter, no_normals).find("no normals; estimate them first"), std::string::npos);
  PointCloud bad_radius = ball;
  bad_radius.radii.assign(100, 1.0);
  bad_radius.radii[5] = -1;
  EXPECT_NE(run_error(*filter, bad_radius).find("vertex 5 has radius -1"), std::string::npos);
  FilterParams bad;
  bad.sigma_g = 0;
  EXPECT_NE(run_error(*filter, ball, bad).find("invalid_argument: invalid filter parameter sigma_g = 0"),
            std::string::npos);
}

TEST_P(NormalFilterTest, DegenerateCloudsFollowSpec) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(GetParam());
  PNF_SKIP_IF_NULL(filter);
  // Empty: nothing to do, nothing wrong.
  EXPECT_TRUE(filter->run(PointCloud{}).normals.empty());

  // One point, absolute units: N(s) = {s}, J = I - n n^T, adj(J)^T = n n^T, so n' = n.
  PointCloud one;
  one.positions = {{1, 2, 3}};
  one.normals = {normalized({1, 1, 0})};
  FilterParams absolute;
  absolute.units = pnf::Units::absolute;
  absolute.sigma_f = 1;
  absolute.sigma_g = 1;
  std::vector<Vec3> out = filter->run(one, absolute).normals;
  EXPECT_LE(angle_deg(out[0], one.normals[0]), 1e-5);
  // In radius units there is no spacing to measure.
  EXPECT_NE(run_error(*filter, one).find("cannot estimate the mean surfel radius of 1 points"), std::string::npos);

  // All points at one place: every weight is 1 with zero slope, so J = mean(I - n_p n_p^T). With
  // normals spread over one hemisphere around +z the result stays on +z's side; with radius units
  // the spacing is 0 and that is an error.
  PointCloud heap;
  std::mt19937 rng(21);
  for (int i = 0; i < 50; ++i) {
    heap.positions.push_back({5, 5, 5});
    heap.normals.push_back(jitter_normal({0, 0, 1}, 20, rng));
  }
  out = filter->run(heap, absolute).normals;
  for (std::size_t i = 0; i < out.size(); ++i) {
    EXPECT_GT(dot(out[i], heap.normals[i]), 0);
    EXPECT_NEAR(norm(out[i]), 1.0, 1e-9);
  }
  EXPECT_NE(run_error(*filter, heap).find("cannot estimate the mean surfel radius"), std::string::npos);
}

// The input's row order changes nothing: the same normals, permuted, bit for bit. Every point's
// neighbours are visited in one order (the curve's, ties by the positions' and then the normals'
// bits), so every sum rounds alike. Exact duplicates, some with other normals, are the ties.
TEST_P(NormalFilterTest, PermutedRowsGiveThePermutedNormals) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(GetParam());
  PNF_SKIP_IF_NULL(filter);
  PointCloud cloud = jittered_sphere(3000, 5.0, 31, 20);
  std::mt19937 rng(33);
  for (std::size_t i = 0; i < 300; i += 3) {
    cloud.positions.push_back(cloud.positions[i]);
    cloud.normals.push_back(i % 2 == 0 ? cloud.normals[i] : jitter_normal(cloud.normals[i], 10, rng));
  }
  std::vector<std::size_t> permutation(cloud.size());
  for (std::size_t i = 0; i < permutation.size(); ++i) permutation[i] = i;
  std::shuffle(permutation.begin(), permutation.end(), rng);
  PointCloud shuffled;
  for (std::size_t i : permutation) {
    shuffled.positions.push_back(cloud.positions[i]);
    shuffled.normals.push_back(cloud.normals[i]);
  }
  FilterParams params;
  params.stop_change_deg = 1e-6;  // the stop rule's sums too
  const std::vector<Vec3> out = filter->run(cloud, params).normals;
  const std::vector<Vec3> out_shuffled = filter->run(shuffled, params).normals;
  for (std::size_t k = 0; k < permutation.size(); ++k) {
    ASSERT_EQ(out_shuffled[k], out[permutation[k]]) << "row " << k << " (input row " << permutation[k] << ")";
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, NormalFilterTest, ::testing::Values(Backend::reference, Backend::opencl),
                         [](const auto& info) { return std::string(pnf::to_string(info.param)); });

}  // namespace

namespace {

TEST(StopRule, PassesEndWhenTheNormalsStopChanging) {
  pnf::PointCloud plane = pnf::test::jittered_grid(40, 1.0, 0.2, 40);
  std::mt19937 rng(41);
  for (pnf::Vec3& n : plane.normals) n = pnf::test::jitter_normal(n, 15, rng);
  pnf::FilterParams params;
  params.iterations = 50;
  params.stop_change_deg = 0.05;
  pnf::FilterResult r = pnf::test::reference_filter()->run(plane, params);
  ASSERT_GE(r.summary.passes_run, 2);
  EXPECT_LT(r.summary.passes_run, 50) << "a plane settles long before 50 passes";
  ASSERT_EQ(r.summary.mean_change_deg.size(), std::size_t(r.summary.passes_run));
  EXPECT_LT(r.summary.mean_change_deg.back(), 0.05);
  for (std::size_t k = 0; k + 1 < r.summary.mean_change_deg.size(); ++k) EXPECT_GE(r.summary.mean_change_deg[k], 0.05);
  // The first change is the whole first pass: independently, the mean angle input -> pass 1.
  params.iterations = 1;
  params.stop_change_deg = 0;
  std::vector<pnf::Vec3> one = pnf::test::reference_filter()->run(plane, params).normals;
  std::vector<pnf::Vec3> unit(plane.size());
  for (std::size_t i = 0; i < plane.size(); ++i) unit[i] = pnf::test::normalized(plane.normals[i]);
  // Within half a quantum: the stop rule counts each angle in whole 2^-16 degrees (change_quanta).
  EXPECT_NEAR(r.summary.mean_change_deg[0], pnf::test::mean_angle_deg(unit, one), 0.5 / 65536);
}

}  // namespace
