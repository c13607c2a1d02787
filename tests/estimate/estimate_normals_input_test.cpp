// Tests of pnf::estimate_normals on awkward input: duplicates, translation, thread-count
// determinism, k and its clamping, curvature, degenerate neighbourhoods, validation, float and
// strided views, orientation names.
#include "pnf/estimate_normals.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "estimate_test_shapes.hpp"
#include "pnf/error.hpp"

namespace pnf {
namespace {

using namespace pnf::test::estimate;
using pnf::test::expect_error;

TEST(EstimateNormals, DuplicatedPointsAreHandled) {
  // Every point twice. A point's own index need not come first among its zero-distance results,
  // yet with k' = 2 k each fit sees exactly the k original points twice over, which leaves the
  // centroid and the normalised covariance, and so the normal, as in the original cloud.
  constexpr int kOriginalK = 16;
  // Summing each offset twice changes only the rounding of the covariance.
  constexpr double kRoundingDegrees = 1e-6;
  const Sample sphere = noisy_sphere(1500, 9);
  std::vector<Vec3> doubled = sphere.positions;
  doubled.insert(doubled.end(), sphere.positions.begin(), sphere.positions.end());

  const std::vector<Vec3> original = estimate_normals(sphere.positions, params_with(Orientation::outward, kOriginalK));
  const std::vector<Vec3> normals = estimate_normals(doubled, params_with(Orientation::outward, 2 * kOriginalK));
  expect_unit_normals(normals, doubled.size());
  for (std::size_t i = 0; i < doubled.size(); ++i) {
    const Vec3& expected = original[i % original.size()];
    ASSERT_GT(dot(normals[i], expected), 0.0) << "point " << i;
    ASSERT_LT(line_angle_degrees(normals[i], expected), kRoundingDegrees) << "point " << i;
  }

  // mst over a graph in which every point has a twin at distance 0.
  std::vector<Vec3> truth = sphere.true_normals;
  truth.insert(truth.end(), sphere.true_normals.begin(), sphere.true_normals.end());
  EXPECT_GE(compare(estimate_normals(doubled, params_with(Orientation::mst)), truth).oriented_share, kOrientedShare);
}

TEST(EstimateNormals, TranslationChangesNothingBeyondRounding) {
  // docs/method.md's bar for the filter: a 1e6 shift in x, y and z moves no normal by more than 0.01°.
  constexpr double kShift = 1e6;
  constexpr double kMaxChangeDegrees = 0.01;
  const Sample sphere = noisy_sphere(2000, 10);
  std::vector<Vec3> shifted = sphere.positions;
  for (Vec3& p : shifted) {
    for (double& c : p) c += kShift;
  }
  const EstimateParams params = params_with(Orientation::mst);
  const std::vector<Vec3> original = estimate_normals(sphere.positions, params);
  const std::vector<Vec3> moved = estimate_normals(shifted, params);
  for (std::size_t i = 0; i < original.size(); ++i) {
    ASSERT_GT(dot(original[i], moved[i]), 0.0) << "point " << i << " flipped";
    ASSERT_LT(line_angle_degrees(original[i], moved[i]), kMaxChangeDegrees) << "point " << i;
  }
}

TEST(EstimateNormals, SameResultForAnyThreadCount) {
#ifdef _OPENMP
  // Three threads on a two-core machine still splits the work three ways (uneven slices, an
  // extra merge level in the mst edge sort), which is what this checks.
  const Sample torus = noisy_torus(5000, 11);
  const int saved = omp_get_max_threads();
  for (const Orientation orientation : {Orientation::outward, Orientation::mst}) {
    SCOPED_TRACE(to_string(orientation));
    omp_set_num_threads(1);
    const std::vector<Vec3> one = estimate_normals(torus.positions, params_with(orientation));
    for (const int threads : {2, 3}) {
      omp_set_num_threads(threads);
      const std::vector<Vec3> many = estimate_normals(torus.positions, params_with(orientation));
      for (std::size_t i = 0; i < one.size(); ++i) {
        ASSERT_EQ(one[i], many[i]) << threads << " threads, point " << i;
      }
    }
  }
  omp_set_num_threads(saved);
#else
  GTEST_SKIP() << "tests built without OpenMP; the thread count cannot be varied";
#endif
}

TEST(EstimateNormals, KLargerThanTheCloudIsClamped) {
  const std::vector<Vec3> corners = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0.001}};
  const std::vector<Vec3> normals = estimate_normals(corners, params_with(Orientation::mst, 100));
  expect_unit_normals(normals, corners.size());
  for (const Vec3& n : normals) EXPECT_GT(n[2], 0.99);

  // Three points is the smallest cloud: k = 3 takes all three and the fit is exact.
  const std::vector<Vec3> triangle = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}};
  for (const Vec3& n : estimate_normals(triangle, params_with(Orientation::mst, 3))) {
    EXPECT_NEAR(std::abs(n[1]), 1.0, 1e-12);
  }
}

// EstimateParams::k counts the point itself, as PCL's setKSearch (`pcl_normal_estimation -k`)
// and Open3D's KDTreeSearchParamKNN do: each normal is the PCA normal of the k nearest points,
// the point included, found by brute force.
TEST(EstimateNormals, KCountsThePointItselfAsPclAndOpen3dDo) {
  // The kd-tree and the brute force find the same points; the fits differ only in rounding.
  constexpr double kRoundingDegrees = 1e-6;
  const Sample sphere = noisy_sphere(400, 21);
  for (const int k : {3, 7, 16}) {
    SCOPED_TRACE("k = " + std::to_string(k));
    const std::vector<Vec3> normals = estimate_normals(sphere.positions, params_with(Orientation::outward, k));
    for (std::size_t i = 0; i < normals.size(); ++i) {
      ASSERT_LT(line_angle_degrees(normals[i], brute_force_fit(sphere.positions, i, k).normal), kRoundingDegrees)
          << "point " << i;
    }
  }
  // The corner's two nearest others lie in z = 0; the third is above it. k = 3 fits the plane
  // z = 0 through the point and those two (with the point plus 3 others it would tilt).
  const std::vector<Vec3> corner = {{0, 0, 0}, {1, 0, 0}, {0, 1.1, 0}, {0, 0, 1.5}};
  EXPECT_NEAR(std::abs(estimate_normals(corner, params_with(Orientation::mst, 3))[0][2]), 1.0, 1e-12);
}

// The curvature overload gives PCL's surface variation lambda0 / (lambda0 + lambda1 + lambda2) of
// the same fit, by brute force; 0 on a plane and for coincident points (PCL's value there), and
// the same normals as the plain call.
TEST(EstimateNormals, CurvatureIsPclsSurfaceVariation) {
  // The ratio's rounding: a 3 x 3 eigenvalue solve is accurate to a few epsilon of the largest
  // eigenvalue, so the ratio to their sum is too; this is far above that.
  constexpr double kTolerance = 1e-9;
  const Sample sphere = noisy_sphere(400, 22);
  for (const int k : {4, 16}) {
    SCOPED_TRACE("k = " + std::to_string(k));
    const EstimateParams params = params_with(Orientation::outward, k);
    std::vector<double> curvature = {1.0};  // replaced
    const std::vector<Vec3> normals = estimate_normals(sphere.positions, curvature, params);
    EXPECT_EQ(normals, estimate_normals(sphere.positions, params));
    ASSERT_EQ(curvature.size(), sphere.positions.size());
    for (std::size_t i = 0; i < curvature.size(); ++i) {
      const std::array<double, 3> lambda = brute_force_fit(sphere.positions, i, k).eigenvalues;
      const double expected = lambda[0] / (lambda[0] + lambda[1] + lambda[2]);
      ASSERT_NEAR(curvature[i], expected, kTolerance) << "point " << i;
      ASSERT_LE(curvature[i], 1.0 / 3.0 + 1e-12) << "point " << i;
    }
  }
  std::vector<Vec3> plane;
  for (int i = 0; i < 30; ++i) plane.push_back({0.1 * (i % 6), 0.13 * (i / 6), 2.0});
  std::vector<double> flat;
  estimate_normals(plane, flat, params_with(Orientation::mst, 8));
  for (const double c : flat) EXPECT_NEAR(c, 0.0, 1e-15);
  std::vector<double> coincident;
  estimate_normals(std::vector<Vec3>(10, Vec3{1, 2, 3}), coincident, params_with(Orientation::mst));
  EXPECT_EQ(coincident, std::vector<double>(10, 0.0));
}

TEST(EstimateNormals, DegenerateNeighbourhoodsGiveFiniteNormals) {
  // All points coincident: no plane exists; the documented answer is +z.
  const std::vector<Vec3> coincident(20, Vec3{0.5, -2.0, 3.0});
  const std::vector<Vec3> normals = estimate_normals(coincident, params_with(Orientation::mst));
  for (const Vec3& n : normals) EXPECT_EQ(n, (Vec3{0.0, 0.0, 1.0}));

  // Collinear points: any unit vector perpendicular to the line is a valid answer.
  std::vector<Vec3> line;
  for (int i = 0; i < 30; ++i) line.push_back({0.1 * i, 0.0, 0.0});
  const std::vector<Vec3> line_normals = estimate_normals(line, params_with(Orientation::outward));
  expect_unit_normals(line_normals, line.size());
  for (const Vec3& n : line_normals) EXPECT_NEAR(n[0], 0.0, 1e-12);
}

TEST(EstimateNormals, ValidationNamesTheBadFieldOrVertex) {
  const std::vector<Vec3> square = noisy_plane(50, 12).positions;
  EstimateParams params;
  params.k = 2;
  expect_error([&] { estimate_normals(square, params); }, ErrorCode::invalid_argument,
               std::vector<std::string>{"k", "2"});
  expect_error([&] { params.validate(); }, ErrorCode::invalid_argument, std::vector<std::string>{"k = 2"});

  params = EstimateParams{};
  params.viewpoint = {0.0, std::numeric_limits<double>::quiet_NaN(), 0.0};
  expect_error([&] { params.validate(); }, ErrorCode::invalid_argument, std::vector<std::string>{"viewpoint"});

  std::vector<Vec3> bad = square;
  bad[7][1] = std::numeric_limits<double>::quiet_NaN();
  bad[9][0] = std::numeric_limits<double>::infinity();
  expect_error([&] { estimate_normals(bad, EstimateParams{}); }, ErrorCode::invalid_input,
               std::vector<std::string>{"vertex 7"});
  bad[7] = square[7];
  expect_error([&] { estimate_normals(bad, EstimateParams{}); }, ErrorCode::invalid_input,
               std::vector<std::string>{"vertex 9"});

  const std::vector<Vec3> two_points = {{0, 0, 0}, {1, 0, 0}};
  expect_error([&] { estimate_normals(two_points, EstimateParams{}); }, ErrorCode::invalid_input,
               std::vector<std::string>{"3 points", "got 2"});
  EXPECT_NO_THROW(EstimateParams{}.validate());
}

// Views of the caller's memory: float rows with a stride, in and out, give the vector call's
// normals to the last bit (float positions widen exactly; the float output is the rounding of
// the double normals), and a strided double view gives them exactly. Every orientation.
TEST(EstimateNormals, FloatAndStridedViewsGiveTheVectorCallsNormals) {
  const Sample sphere = noisy_sphere(3000, 21);
  struct FloatRow {
    float position[3];
    float normal[3];
    float extra;  // another field of the caller's record
  };
  struct DoubleRow {
    double normal[3];
    double extra;
  };
  const std::size_t n = sphere.positions.size();
  std::vector<FloatRow> rows(n);
  std::vector<Vec3> widened(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) rows[i].position[c] = float(sphere.positions[i][c]);
  }
  // Widened in a loop of its own: GCC 12 at -O2 can forward the unrounded double into the
  // store-then-read of one loop (seen in auto_params_test).
  for (std::size_t i = 0; i < n; ++i) widened[i] = {rows[i].position[0], rows[i].position[1], rows[i].position[2]};
  const Vec3ArrayView positions(rows[0].position, n, ScalarType::float32, sizeof(FloatRow));
  for (const Orientation orientation : {Orientation::viewpoint, Orientation::outward, Orientation::mst}) {
    SCOPED_TRACE(to_string(orientation));
    const std::vector<Vec3> expected = estimate_normals(widened, params_with(orientation));
    estimate_normals(positions, MutableVec3ArrayView(rows[0].normal, n, ScalarType::float32, sizeof(FloatRow)),
                     params_with(orientation));
    std::vector<DoubleRow> out(n);
    estimate_normals(positions, MutableVec3ArrayView(out[0].normal, n, ScalarType::float64, sizeof(DoubleRow)),
                     params_with(orientation));
    std::size_t differing = 0;
    for (std::size_t i = 0; i < n; ++i) {
      for (int c = 0; c < 3; ++c) {
        differing += out[i].normal[c] != expected[i][c] || rows[i].normal[c] != float(expected[i][c]);
      }
    }
    EXPECT_EQ(differing, 0u);
  }
  std::vector<Vec3> short_output(n - 1);
  expect_error([&] { estimate_normals(positions, MutableVec3ArrayView(short_output), EstimateParams{}); },
               ErrorCode::invalid_argument, std::vector<std::string>{"output", std::to_string(n - 1)});
}

TEST(EstimateNormals, OrientationNamesRoundTrip) {
  for (const Orientation orientation : {Orientation::viewpoint, Orientation::outward, Orientation::mst}) {
    EXPECT_EQ(parse_orientation(to_string(orientation)), orientation);
  }
  expect_error([] { parse_orientation("inward"); }, ErrorCode::invalid_argument,
               std::vector<std::string>{"inward", "viewpoint, outward, mst"});
}

}  // namespace
}  // namespace pnf
