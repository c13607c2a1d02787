// --auto's judge (lib/src/auto/surface_judge.hpp) and the judged run (pnf::improve_normals_auto),
// against true normals the tests know.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "auto/sample_neighbourhoods.hpp"
#include "auto/surface_judge.hpp"
#include "crease_clouds.hpp"
#include "pnf/estimate_normals.hpp"
#include "pnf/improve_normals_auto.hpp"
#include "spatial/spatial_index.hpp"
#include "spatial/spatial_order.hpp"
#include "test_clouds.hpp"

namespace pnf::test {
namespace {

// The judge keeps copies of the neighbourhoods, so the index may go.
detail::SurfaceJudge judge_of(const std::vector<Vec3>& positions, int neighbours, double width) {
  std::vector<double> xyz = xyz_rows(positions);
  const detail::SpatialIndex index(std::move(xyz), detail::SpatialIndex::Layout::any_order);
  const std::vector<std::uint32_t> curve = detail::morton_order(Vec3ArrayView(positions));
  const detail::SampleNeighbourhoods n =
      detail::sample_neighbourhoods(index, curve, detail::ranks_of(curve), 2000, neighbours, {}, "test");
  return detail::SurfaceJudge(index.positions(), n, width);
}

// Each normal tilted by exactly `degrees` about a random tangent direction.
std::vector<Vec3> tilted(const std::vector<Vec3>& truth, double degrees, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> turn(0, 2 * kPi);
  std::vector<Vec3> out;
  const double t = degrees * kPi / 180;
  for (const Vec3& n : truth) {
    const Vec3 a = std::abs(n[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    Vec3 t1 = normalized({n[1] * a[2] - n[2] * a[1], n[2] * a[0] - n[0] * a[2], n[0] * a[1] - n[1] * a[0]});
    const Vec3 t2 = {n[1] * t1[2] - n[2] * t1[1], n[2] * t1[0] - n[0] * t1[2], n[0] * t1[1] - n[1] * t1[0]};
    const double phi = turn(rng);
    Vec3 d;
    for (int c = 0; c < 3; ++c) d[c] = std::cos(phi) * t1[c] + std::sin(phi) * t2[c];
    out.push_back({std::cos(t) * n[0] + std::sin(t) * d[0], std::cos(t) * n[1] + std::sin(t) * d[1],
                   std::cos(t) * n[2] + std::sin(t) * d[2]});
  }
  return out;
}

TEST(SurfaceJudge, ReadsATiltOnASmoothSurfaceAsItsAngle) {
  const PointCloud s = sphere(20000, 1.0, 3);
  const double spacing = std::sqrt(4 * kPi / 20000);
  const detail::SurfaceJudge judge = judge_of(s.positions, 65, 0.15 * spacing);
  ASSERT_FALSE(judge.empty());
  const std::vector<Vec3>& truth = s.normals;
  EXPECT_LT(judge.rms_deg(xyz_rows(truth).data()), 0.3);
  // A tilt of 5 degrees reads as 5, within the fits' own error.
  EXPECT_NEAR(judge.rms_deg(xyz_rows(tilted(truth, 5, 1)).data()), 5.0, 0.5);
  EXPECT_NEAR(judge.rms_deg(xyz_rows(tilted(truth, 2, 2)).data()), 2.0, 0.4);
}

// On a plane every fit is exact in any frame (the height is linear in the tangent coordinates),
// so the judged angle is the tilt to rounding: a wrong term in the fit's normal equations would
// move it. The plane is turned off the axes; the tilts turn each normal a different way.
TEST(SurfaceJudge, ReadsTheTiltsOfAPlaneExactly) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> coordinate(-1, 1);
  const Vec3 n = normalized({0.3, -0.5, 0.8});
  const Vec3 a = normalized({n[1], -n[0], 0});
  const Vec3 b = {n[1] * a[2] - n[2] * a[1], n[2] * a[0] - n[0] * a[2], n[0] * a[1] - n[1] * a[0]};
  std::vector<Vec3> positions;
  for (int i = 0; i < 5000; ++i) {
    const double u = coordinate(rng), v = coordinate(rng);
    positions.push_back({u * a[0] + v * b[0] + 5, u * a[1] + v * b[1] - 2, u * a[2] + v * b[2] + 1});
  }
  const detail::SurfaceJudge judge = judge_of(positions, 257, 0.004);
  ASSERT_FALSE(judge.empty());
  for (double degrees : {0.0, 3.0, 20.0}) {
    const std::vector<Vec3> truth(positions.size(), n);
    EXPECT_NEAR(judge.rms_deg(xyz_rows(tilted(truth, degrees, 7)).data()), degrees, 1e-6) << degrees;
  }
}

// A quadric height field z = q(x, y), judged with every normal along z: in that one frame each
// neighbourhood's heights are exactly quadratic in its tangent coordinates, so with weights near
// 1 (a wide width) the fit is exact and each point's judged angle is atan |grad q| there. Every
// term of the fit's normal equations enters (the plane above checks only the linear ones).
TEST(SurfaceJudge, FitsAQuadricExactly) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> coordinate(-1, 1);
  std::vector<Vec3> positions;
  double expected = 0;
  const int points = 1500;  // under judge_of's 2000 samples: every point is one
  for (int i = 0; i < points; ++i) {
    const double x = coordinate(rng), y = coordinate(rng);
    positions.push_back({x, y, 0.3 * x * x + 0.2 * x * y - 0.4 * y * y + 0.1 * x - 0.2 * y});
    const double angle = std::atan(std::hypot(0.6 * x + 0.2 * y + 0.1, 0.2 * x - 0.8 * y - 0.2));
    expected += angle * angle;
  }
  expected = std::sqrt(expected / points) * 180 / kPi;
  const detail::SurfaceJudge judge = judge_of(positions, 65, 100.0);
  ASSERT_EQ(judge.size(), std::size_t(points));
  const std::vector<Vec3> up(positions.size(), Vec3{0, 0, 1});
  EXPECT_NEAR(judge.rms_deg(xyz_rows(up).data()), expected, 1e-6);
}

TEST(SurfaceJudge, PrefersEachFacesOwnNormalAtASharpCrease) {
  const Crease c = make_crease(90, 20000, 0.0, 5);
  const detail::SurfaceJudge judge = judge_of(c.cloud.positions, 65, 0.15 * c.spacing);
  // PCA normals blur the crease; the true ones are each face's.
  const std::vector<Vec3> pca = pca16_normals(c.cloud.positions, c.truth);
  ASSERT_GT(rms_line_angle(pca, c.truth), 2.0);  // the blur is there to be seen
  const double truth_score = judge.rms_deg(xyz_rows(c.truth).data());
  const double pca_score = judge.rms_deg(xyz_rows(pca).data());
  EXPECT_LT(truth_score, 0.5);
  EXPECT_GT(pca_score, 0.5 * rms_line_angle(pca, c.truth));
}

// Ripples z = a sin(k x) sin(k y) of wavelength 0.4, the whole neighbourhood (radius about 0.09)
// spanning nearly half of one: a quadric over all of it cannot follow them, one over its nearest
// quarter can. The judge scores with the quarter there, and its score of the true normals falls.
TEST(SurfaceJudge, ScoresDetailFinerThanItsNeighbourhoodWithTheNearestQuarter) {
  const PointCloud ripples = rippled_grid();
  detail::SurfaceJudge judge = judge_of(ripples.positions, 257, 0.15 * 0.01);
  const std::vector<double> truth = xyz_rows(ripples.normals);
  const double whole = judge.rms_deg(truth.data());
  judge.choose_scale(truth.data());
  EXPECT_EQ(judge.scored(), 64);
  EXPECT_LT(judge.rms_deg(truth.data()), 0.5 * whole);
}

// A jittered grid of spacing 0.01 on the plane z = 0, its points moved off it by Gaussian noise of
// 0.3 spacings (its normals stay the plane's).
PointCloud noisy_plane() {
  PointCloud plane = jittered_grid(100, 0.01, 0.3, 8);
  std::mt19937 rng(9);
  std::normal_distribution<double> noise(0, 0.003);
  for (Vec3& p : plane.positions) p[2] = noise(rng);
  return plane;
}

// On a plane with noise of 0.3 spacings normal to it, the whole neighbourhood averages the noise
// better: the judge keeps it.
TEST(SurfaceJudge, ScoresNoisyPositionsWithTheWholeNeighbourhood) {
  const PointCloud plane = noisy_plane();
  detail::SurfaceJudge judge = judge_of(plane.positions, 257, std::hypot(0.15 * 0.01, 2 * 0.003));
  const std::vector<double> truth = xyz_rows(plane.normals);
  judge.choose_scale(truth.data());
  EXPECT_EQ(judge.scored(), 257);
}

// choose_scale keeps the input's sums at the scale it chose, so that the input is fitted once:
// they are those of fitting it again there, to the bit; a change of scale drops them.
TEST(SurfaceJudge, KeepsTheInputsSumsAtTheScaleChosen) {
  PointCloud plane = jittered_grid(100, 0.01, 0.3, 8);
  const std::vector<double> input = xyz_rows(tilted(plane.normals, 5, 3));
  for (int quarter = 0; quarter < 2; ++quarter) {
    // The ripples' detail makes the judge choose the quarter; the flat plane, the whole.
    if (quarter) {
      for (Vec3& p : plane.positions) p[2] = 0.01 * std::sin(2 * kPi / 0.4 * p[0]) * std::sin(2 * kPi / 0.4 * p[1]);
    }
    detail::SurfaceJudge judge = judge_of(plane.positions, 257, 0.15 * 0.01);
    judge.choose_scale(input.data());
    ASSERT_EQ(judge.scored(), quarter ? 64 : 257);
    const detail::SurfaceJudge::Sums kept = judge.input_sums(nullptr);  // not read: the kept sums answer
    const detail::SurfaceJudge::Sums fitted = judge.sums(input.data());
    EXPECT_EQ(kept.samples, judge.size());
    EXPECT_EQ(kept.squared, fitted.squared);
    EXPECT_EQ(kept.own_error_squared(), fitted.own_error_squared());
    EXPECT_EQ(judge.input_rms_deg(nullptr), judge.rms_deg(input.data()));
    EXPECT_EQ(kept.own_error_deg(), judge.own_error_deg(input.data()));
    judge.score_with(quarter ? 257 : 64);
    EXPECT_EQ(judge.input_sums(input.data()).squared, judge.sums(input.data()).squared);
    EXPECT_NE(judge.input_sums(input.data()).squared, kept.squared);
  }
}

// PCA normals over k points (`pnf estimate`'s, an independent implementation) follow the plane of
// exactly their own k nearest; the ripples make every other count's plane differ. The widest plane
// tried (256 of 257) tells nothing: exact normals on a noisy plane are nearest it too.
TEST(SurfaceJudge, FindsTheSupportOfPcaNormals) {
  const PointCloud ripples = rippled_grid();
  const detail::SurfaceJudge judge = judge_of(ripples.positions, 257, 0.15 * 0.01);
  for (int k : {16, 32, 64, 128, 256}) {
    EstimateParams params;
    params.k = k;
    EXPECT_EQ(judge.input_support(xyz_rows(estimate_normals(ripples.positions, params)).data()), k < 256 ? k : 0) << k;
  }
  const PointCloud plane = noisy_plane();
  EXPECT_EQ(judge_of(plane.positions, 257, 0.01).input_support(xyz_rows(plane.normals).data()), 0);
}

// PCA normals over k points are the planes of their nearest k points, for any k (`pnf estimate`'s,
// an independent implementation), also rounded to floats as a file stores them; the true normals,
// and PCA normals tilted by a hundredth of a degree (ten times the tolerance), are no count's.
TEST(SurfaceJudge, RecognisesPlaneFitNormalsOfAnyCount) {
  const PointCloud ripples = rippled_grid();
  const detail::SurfaceJudge judge = judge_of(ripples.positions, 257, 0.15 * 0.01);
  EstimateParams params;
  for (int k : {10, 16, 24, 64}) {
    params.k = k;
    std::vector<double> pca = xyz_rows(estimate_normals(ripples.positions, params));
    EXPECT_EQ(judge.plane_fit_count(pca.data()), k) << k;
    for (double& v : pca) v = double(float(v));
    EXPECT_EQ(judge.plane_fit_count(pca.data()), k) << k << ", as floats";
  }
  EXPECT_EQ(judge.plane_fit_count(xyz_rows(ripples.normals).data()), 0);
  params.k = 16;
  const std::vector<Vec3> pca16 = estimate_normals(ripples.positions, params);
  EXPECT_EQ(judge.plane_fit_count(xyz_rows(tilted(pca16, 0.01, 5)).data()), 0);
}

// Where the input normals are PCA normals over 64 points, the judge fits 32 (half of them):
// fitting their own points it shares their smoothing of the ripples and reads them low; under
// them it reads them nearer their true error. PCA-16 normals leave the choice as it was.
TEST(SurfaceJudge, FitsUnderTheSupportOfWidePcaNormals) {
  const PointCloud ripples = rippled_grid();
  EstimateParams params;
  params.k = 64;
  const std::vector<Vec3> pca64 = estimate_normals(ripples.positions, params);
  const std::vector<double> input = xyz_rows(pca64);
  detail::SurfaceJudge judge = judge_of(ripples.positions, 257, 0.15 * 0.01);
  judge.score_with(64);
  const double at_their_own = judge.rms_deg(input.data());
  judge.choose_scale(input.data());
  EXPECT_EQ(judge.under_support(), 64);
  EXPECT_EQ(judge.scored(), 32);
  const double truth = rms_line_angle(pca64, ripples.normals);
  EXPECT_LT(std::abs(judge.input_rms_deg(input.data()) - truth), std::abs(at_their_own - truth));

  params.k = 16;
  const std::vector<double> pca16 = xyz_rows(estimate_normals(ripples.positions, params));
  detail::SurfaceJudge other = judge_of(ripples.positions, 257, 0.15 * 0.01);
  other.choose_scale(pca16.data());
  EXPECT_EQ(other.under_support(), 0);
  EXPECT_EQ(other.scored(), 64);  // the ripples' detail: the quarter, as for the true normals
}

// The quarter may score only where the positions are as clean as the fits' floor (twice the noise
// under 0.15 spacings): there its fits hold no noise that filtered normals could share.
TEST(SurfaceJudge, QuarterOnlyOnCleanPositions) {
  DataEstimate e;
  e.area_spacing = 1;
  e.fit_neighbours = 64;
  e.position_noise = 0.05;
  EXPECT_TRUE(detail::judge_geometry(e).quarter_allowed);
  e.position_noise = 0.1;
  EXPECT_FALSE(detail::judge_geometry(e).quarter_allowed);
}

TEST(ImproveNormalsAuto, KeepsNormalsThatAlreadyFollowTheSurface) {
  // A clean sphere with its exact normals: every pass can only move them off; the input is kept.
  const PointCloud s = sphere(20000, 1.0, 4);
  std::vector<Vec3> out(s.size());
  const AutoRun run = improve_normals_auto(s, MutableVec3ArrayView(out), fastest_filter());
  EXPECT_EQ(run.passes_kept, 0);
  EXPECT_EQ(run.choice.params.iterations, 0);
  EXPECT_LT(mean_angle_deg(out, s.normals), 1e-9);
}

TEST(ImproveNormalsAuto, FiltersBlurredCreasesAndKeepsTheBestPass) {
  const Crease c = make_crease(90, 20000, 0.1, 6);
  PointCloud cloud = c.cloud;
  cloud.normals = pca16_normals(cloud.positions, c.truth);
  const double input = rms_line_angle(cloud.normals, c.truth);
  // In place: the output view is the cloud's own normals.
  const AutoRun run = improve_normals_auto(cloud, MutableVec3ArrayView(cloud.normals), fastest_filter());
  EXPECT_GT(run.passes_kept, 0);
  EXPECT_LT(rms_line_angle(cloud.normals, c.truth), 0.7 * input);
  // The passes end within two of the best, and the best is the lowest judged.
  ASSERT_FALSE(run.judged_rms_deg.empty());
  EXPECT_LE(run.summary.passes_run, run.passes_kept + 2);
  EXPECT_FALSE(run.choice.judged.empty());
}

TEST(ImproveNormalsAuto, ReportsItsEstimateAndCanBeCancelledThere) {
  const PointCloud s = sphere(5000, 1.0, 2);
  std::vector<Vec3> out(s.size(), Vec3{0, 0, 0});
  std::vector<ProgressStage> stages;
  const ProgressCallback stop_after_estimate = [&](const PassProgress& p) {
    stages.push_back(p.stage);
    return !(p.stage == ProgressStage::estimate && p.fraction >= 1);
  };
  try {
    improve_normals_auto(s, MutableVec3ArrayView(out), fastest_filter(), stop_after_estimate);
    FAIL() << "not cancelled";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::cancelled) << e.what();
  }
  // The estimate's start, its fits (about every 0.1 s; the first at once), its end: all stage
  // estimate, and nothing after the cancel.
  ASSERT_GE(stages.size(), 3u);
  for (ProgressStage stage : stages) EXPECT_EQ(stage, ProgressStage::estimate);
  EXPECT_EQ(out[0][0], 0.0);  // nothing written
}

// The judged passes run in slices like any others (filter_engine.cpp): a cancel within the first
// pass ends the run there, before the pass is done, and nothing is written.
TEST(ImproveNormalsAuto, CanBeCancelledWithinAJudgedPass) {
  const Crease c = make_crease(90, 20000, 0.1, 6);
  PointCloud cloud = c.cloud;
  cloud.normals = pca16_normals(cloud.positions, c.truth);
  std::vector<Vec3> out(cloud.size(), Vec3{0, 0, 0});
  int passes_done = 0;
  const ProgressCallback stop_within_a_pass = [&](const PassProgress& p) {
    passes_done += p.stage == ProgressStage::pass;
    return p.stage != ProgressStage::filtering;
  };
  try {
    improve_normals_auto(cloud, MutableVec3ArrayView(out), fastest_filter(), stop_within_a_pass);
    FAIL() << "not cancelled";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::cancelled) << e.what();
    EXPECT_NE(std::string(e.what()).find("during pass 1"), std::string::npos) << e.what();
  }
  EXPECT_EQ(passes_done, 0);
  EXPECT_EQ(out[0][0], 0.0);  // nothing written
}

// A cancel during the estimate's fits: the first fit report comes at once, so this does not
// depend on the machine's speed.
TEST(ImproveNormalsAuto, CanBeCancelledWithinTheEstimatesSearches) {
  const PointCloud s = sphere(20000, 1.0, 3);
  std::vector<Vec3> out(s.size(), Vec3{0, 0, 0});
  int reports = 0;
  const ProgressCallback stop_in_the_fits = [&](const PassProgress& p) {
    ++reports;
    EXPECT_EQ(p.stage, ProgressStage::estimate);
    return !(p.fraction > 0 && p.fraction < 1);
  };
  try {
    improve_normals_auto(s, MutableVec3ArrayView(out), fastest_filter(), stop_in_the_fits);
    FAIL() << "not cancelled";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::cancelled) << e.what();
    EXPECT_NE(std::string(e.what()).find("searching the samples' neighbours"), std::string::npos) << e.what();
  }
  EXPECT_EQ(reports, 3);  // the start, the first search's start, then its first report within
  EXPECT_EQ(out[0][0], 0.0);
}

// Without normals (or with a zero one) the run is refused with the filter's reason, before the
// estimate and the judge read them (a cloud without normals once crashed the judge).
TEST(ImproveNormalsAuto, RefusesACloudWithoutNormalsOrWithAZeroNormal) {
  PointCloud s = sphere(3000, 1.0, 1);
  std::vector<Vec3> out(s.size());
  PointCloud none = s;
  none.normals.clear();
  try {
    improve_normals_auto(none, MutableVec3ArrayView(out), fastest_filter());
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_input);
    EXPECT_NE(std::string(e.what()).find("improve_normals_auto: the cloud has no normals"), std::string::npos)
        << e.what();
  }
  s.normals[17] = {0, 0, 0};
  try {
    improve_normals_auto(s, MutableVec3ArrayView(out), fastest_filter());
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_input);
    EXPECT_NE(std::string(e.what()).find("vertex 17"), std::string::npos) << e.what();
  }
}

TEST(ImproveNormalsAuto, RefusesAnOutputOfTheWrongSize) {
  const PointCloud s = sphere(100, 1.0, 1);
  std::vector<Vec3> out(99);
  EXPECT_THROW(improve_normals_auto(s, MutableVec3ArrayView(out), fastest_filter()), Error);
}

}  // namespace
}  // namespace pnf::test
