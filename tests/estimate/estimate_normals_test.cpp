// Tests of pnf::estimate_normals against analytic normals of sampled shapes (plane, sphere, cube,
// torus): accuracy, progress and cancelling, and every orientation mode.
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

TEST(EstimateNormals, NoisyPlaneNormalsAreWithinAFewDegrees) {
  const Sample plane = noisy_plane(2000, 1);
  const std::vector<Vec3> normals = estimate_normals(plane.positions, params_with(Orientation::mst));
  expect_unit_normals(normals, plane.positions.size());
  const Agreement agreement = compare(normals, plane.true_normals);
  EXPECT_LT(agreement.max_angle_degrees, kPlaneMaxAngleDegrees) << "point " << agreement.worst_index;
  EXPECT_LT(agreement.mean_angle_degrees, kMeanAngleDegrees);
  // The true normal has n_z > 0, which is where the mst seed rule points an open sheet.
  EXPECT_EQ(agreement.oriented_share, 1.0);
}

// Progress comes on the calling thread, lists (the k-nearest search) first and then estimate,
// each ending at 1; the normals are those of a run without a callback. A false answer in either
// stage cancels with Error(cancelled) and leaves the output as it was.
TEST(EstimateNormals, ProgressIsReportedByStageAndCanCancel) {
  const Sample plane = noisy_plane(2000, 1);
  const EstimateParams params = params_with(Orientation::mst);
  const std::thread::id caller = std::this_thread::get_id();
  std::vector<PassProgress> seen;
  const std::vector<Vec3> watched = estimate_normals(plane.positions, params, [&](const PassProgress& p) {
    EXPECT_EQ(std::this_thread::get_id(), caller);
    seen.push_back(p);
    return true;
  });
  EXPECT_EQ(watched, estimate_normals(plane.positions, params));
  ASSERT_GE(seen.size(), 4u);  // at least the first poll and the end of lists, two ends in estimate
  EXPECT_EQ(seen.front().stage, ProgressStage::lists);
  EXPECT_EQ(seen.back().stage, ProgressStage::estimate);
  EXPECT_EQ(seen.back().fraction, 1.0);
  for (std::size_t i = 1; i < seen.size(); ++i) {
    EXPECT_GE(int(seen[i].stage), int(seen[i - 1].stage)) << "report " << i;
    if (seen[i].stage == seen[i - 1].stage) EXPECT_GE(seen[i].fraction, seen[i - 1].fraction) << "report " << i;
  }
  for (const ProgressStage stop_in : {ProgressStage::lists, ProgressStage::estimate}) {
    std::vector<Vec3> out(plane.positions.size(), Vec3{7, 7, 7});
    try {
      estimate_normals(Vec3ArrayView(plane.positions), MutableVec3ArrayView(out), params,
                       [&](const PassProgress& p) { return p.stage != stop_in; });
      ADD_FAILURE() << "not cancelled in stage " << to_string(stop_in);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::cancelled) << e.what();
    }
    for (const Vec3& n : out) ASSERT_EQ(n, (Vec3{7, 7, 7})) << "written after a cancel in " << to_string(stop_in);
  }
}

TEST(EstimateNormals, ViewpointOrientationFacesTheViewpoint) {
  const Sample plane = noisy_plane(1000, 2);
  EstimateParams params = params_with(Orientation::viewpoint);
  params.viewpoint = {0.3, -0.2, 4.0};
  const Agreement above = compare(estimate_normals(plane.positions, params), plane.true_normals);
  EXPECT_EQ(above.oriented_share, 1.0);
  EXPECT_LT(above.max_angle_degrees, kPlaneMaxAngleDegrees);

  params.viewpoint = {-0.5, 0.1, -4.0};
  const Agreement below = compare(estimate_normals(plane.positions, params), plane.true_normals);
  EXPECT_EQ(below.oriented_share, 0.0);
}

TEST(EstimateNormals, ViewpointAtSphereCentreTurnsAllNormalsInward) {
  const Sample sphere = noisy_sphere(2000, 3, {2.0, -1.0, 0.5});
  EstimateParams params = params_with(Orientation::viewpoint);
  params.viewpoint = {2.0, -1.0, 0.5};
  const Agreement agreement = compare(estimate_normals(sphere.positions, params), sphere.true_normals);
  EXPECT_EQ(agreement.oriented_share, 0.0);
}

TEST(EstimateNormals, SphereOutwardAndMstAgreeWithTheTrueNormal) {
  const Sample sphere = noisy_sphere(4000, 4);
  for (const Orientation orientation : {Orientation::outward, Orientation::mst}) {
    SCOPED_TRACE(to_string(orientation));
    const std::vector<Vec3> normals = estimate_normals(sphere.positions, params_with(orientation));
    expect_unit_normals(normals, sphere.positions.size());
    const Agreement agreement = compare(normals, sphere.true_normals);
    EXPECT_GE(agreement.oriented_share, kOrientedShare);
    EXPECT_LT(agreement.max_angle_degrees, kSphereMaxAngleDegrees) << "point " << agreement.worst_index;
    EXPECT_LT(agreement.mean_angle_degrees, kMeanAngleDegrees);
  }
}

TEST(EstimateNormals, CubeWithMstIsOrientedOutward) {
  // Normals near the sharp edges are blends of two faces (the angle test does not apply there),
  // but their sign must still follow the face each point lies on.
  const Sample cube = noisy_cube(6000, 5);
  const std::vector<Vec3> normals = estimate_normals(cube.positions, params_with(Orientation::mst));
  expect_unit_normals(normals, cube.positions.size());
  EXPECT_GE(compare(normals, cube.true_normals).oriented_share, kOrientedShare);
}

TEST(EstimateNormals, TorusWithMstIsOrientedOutwardWhereOutwardModeCannotBe) {
  const Sample torus = noisy_torus(6000, 6);
  const std::vector<Vec3> normals = estimate_normals(torus.positions, params_with(Orientation::mst));
  expect_unit_normals(normals, torus.positions.size());
  const Agreement agreement = compare(normals, torus.true_normals);
  EXPECT_GE(agreement.oriented_share, kOrientedShare);
  EXPECT_LT(agreement.mean_angle_degrees, kTorusMeanAngleDegrees);

  // The inner half of the torus faces the centroid, so the centroid rule gets it wrong: this is
  // what mst is for, and it shows the test can tell the two apart.
  const Agreement outward =
      compare(estimate_normals(torus.positions, params_with(Orientation::outward)), torus.true_normals);
  EXPECT_LT(outward.oriented_share, 0.9);
}

TEST(EstimateNormals, MstSeedsEveryConnectedComponent) {
  Sample two = noisy_sphere(2000, 7, {0.0, 0.0, 0.0});
  const Sample other = noisy_sphere(1500, 8, {5.0, 1.0, -3.0}, 0.8);
  two.positions.insert(two.positions.end(), other.positions.begin(), other.positions.end());
  two.true_normals.insert(two.true_normals.end(), other.true_normals.begin(), other.true_normals.end());
  const std::vector<Vec3> normals = estimate_normals(two.positions, params_with(Orientation::mst));
  EXPECT_GE(compare(normals, two.true_normals).oriented_share, kOrientedShare);
}

}  // namespace
}  // namespace pnf
