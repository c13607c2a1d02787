// pnf::mpi::improve_normals and choose_filter_params against one process: run under
// `mpirun -np P` (P = 1 .. 4), every rank runs every test. Rank 0 computes the one-process answer
// on the whole cloud and broadcasts it; each rank passes a slice of the cloud (even, uneven,
// empty, all on one rank) and checks its normals against the matching rows.
#include "pnf/mpi.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <random>

#include "agreement.hpp"
#include "partition.hpp"
#include "pnf/bounding_box.hpp"
#include "pnf/device.hpp"
#include "pnf/error.hpp"
#include "pnf/estimate_normals.hpp"
#include "pnf/improve_normals.hpp"
#include "pnf/improve_normals_auto.hpp"
#include "pnf/mean_radius.hpp"
#include "pnf/synthetic_shapes.hpp"
#include "test_clouds.hpp"

namespace {

using namespace pnf;
using pnf::test::angle_deg;

int rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}
int ranks() {
  int p = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &p);
  return p;
}

// The one case a test that needs OpenCL may skip: PNF_DEVICE unset and no OpenCL device at all
// (every rank sees the same). Any other failure of an OpenCL run fails the test.
bool no_opencl_device(std::string& why) {
  if (std::getenv(kDeviceEnvironmentVariable)) return false;
  if (!list_devices().empty()) return false;
  why = "no OpenCL device (set PNF_DEVICE to make this a failure)";
  return true;
}

FilterOptions reference_options() {
  FilterOptions options;
  options.device = Device::reference();
  options.reference_threads = 1;  // ranks share the 2 cores
  return options;
}

// The one-process result on rank 0, sent to every rank.
FilterResult one_process(const PointCloud& cloud, const FilterParams& params, const FilterOptions& options) {
  FilterResult result;
  result.normals.resize(cloud.size());
  if (rank() == 0) result = improve_normals(cloud, params, options);
  MPI_Bcast(result.normals.data(), int(3 * cloud.size()), MPI_DOUBLE, 0, MPI_COMM_WORLD);
  MPI_Bcast(&result.summary.mean_radius, 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  MPI_Bcast(&result.summary.passes_run, 1, MPI_INT, 0, MPI_COMM_WORLD);
  return result;
}

// Rank r's slice [first[r], first[r + 1]) of the cloud.
using Split = std::function<std::vector<std::size_t>(std::size_t n, int ranks)>;

std::vector<std::size_t> even(std::size_t n, int p) {
  std::vector<std::size_t> first(std::size_t(p) + 1);
  for (int r = 0; r <= p; ++r) first[std::size_t(r)] = n * std::size_t(r) / std::size_t(p);
  return first;
}
// Rank 0 holds 90%, the others share the rest.
std::vector<std::size_t> uneven(std::size_t n, int p) {
  std::vector<std::size_t> first(std::size_t(p) + 1, n);
  first[0] = 0;
  if (p == 1) return first;
  const std::size_t big = n * 9 / 10;
  for (int r = 1; r < p; ++r) first[std::size_t(r)] = big + (n - big) * std::size_t(r - 1) / std::size_t(p - 1);
  return first;
}
// Every point on the last rank; the others pass none.
std::vector<std::size_t> all_on_last(std::size_t n, int p) {
  std::vector<std::size_t> first(std::size_t(p) + 1, 0);
  first[std::size_t(p)] = n;
  return first;
}
// Rank 1 (when there is one) passes none, the others share evenly.
std::vector<std::size_t> one_empty(std::size_t n, int p) {
  std::vector<std::size_t> first = even(n, p);
  if (p > 1) first[1] = first[2];  // rank 0 takes rank 1's share
  return first;
}

PointCloud slice(const PointCloud& cloud, std::size_t begin, std::size_t end) {
  PointCloud part;
  part.positions.assign(cloud.positions.begin() + std::ptrdiff_t(begin), cloud.positions.begin() + std::ptrdiff_t(end));
  if (!cloud.normals.empty()) {
    part.normals.assign(cloud.normals.begin() + std::ptrdiff_t(begin), cloud.normals.begin() + std::ptrdiff_t(end));
  }
  if (!cloud.radii.empty()) {
    part.radii.assign(cloud.radii.begin() + std::ptrdiff_t(begin), cloud.radii.begin() + std::ptrdiff_t(end));
  }
  return part;
}

struct Comparison {
  double max_deg = 0;
  bool identical = true;
};

// Runs the distributed filter on this rank's slice and compares with the one-process normals.
Comparison compare(const PointCloud& cloud, const Split& split, const FilterParams& params,
                   const FilterOptions& options, const FilterResult& expected, mpi::DistributedSummary* out = nullptr) {
  const std::vector<std::size_t> first = split(cloud.size(), ranks());
  const std::size_t begin = first[std::size_t(rank())], end = first[std::size_t(rank()) + 1];
  const PointCloud part = slice(cloud, begin, end);
  std::vector<Vec3> normals(part.size());
  const mpi::DistributedSummary summary =
      mpi::improve_normals(MPI_COMM_WORLD, CloudView(part), MutableVec3ArrayView(normals), params, options);
  Comparison c;
  for (std::size_t i = 0; i < part.size(); ++i) {
    const Vec3& want = expected.normals[begin + i];
    c.max_deg = std::max(c.max_deg, angle_deg(normals[i], want));
    if (normals[i] != want) c.identical = false;
  }
  MPI_Allreduce(MPI_IN_PLACE, &c.max_deg, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  int identical = c.identical ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &identical, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  c.identical = identical == 1;
  EXPECT_EQ(summary.points, cloud.size());
  EXPECT_EQ(summary.ranks, ranks());
  EXPECT_EQ(summary.local.mean_radius, expected.summary.mean_radius) << "the mean radius is not the one process's";
  EXPECT_EQ(summary.local.passes_run, expected.summary.passes_run);
  if (out) *out = summary;
  return c;
}

const SyntheticCloud& house() {
  static const SyntheticCloud h = make_scanned_house(12000);
  return h;
}

TEST(MpiFilter, HouseMatchesOneProcessOnEveryPartition) {
  FilterParams params;  // the paper's defaults; the mean radius estimated
  const FilterResult expected = one_process(house().cloud, params, reference_options());
  const std::pair<const char*, Split> splits[] = {
      {"even", even}, {"uneven", uneven}, {"one rank empty", one_empty}, {"all on the last rank", all_on_last}};
  for (const auto& [name, split] : splits) {
    mpi::DistributedSummary summary;
    const Comparison c = compare(house().cloud, split, params, reference_options(), expected, &summary);
    // docs/method.md, "Distributed runs (MPI)": every rank orders, re-centres and lists its points
    // as one process does the whole cloud, so the normals are one process's, bit for bit.
    EXPECT_TRUE(c.identical) << name << ": largest angle " << c.max_deg << " deg";
    if (rank() == 0) {
      std::printf("[ rank 0   ] %-22s P=%d max %.3g deg, %s; owned %zu..%zu, halo %zu..%zu, %zu B/pass\n", name,
                  ranks(), c.max_deg, c.identical ? "bit-identical" : "not bit-identical", summary.owned_min,
                  summary.owned_max, summary.halo_min, summary.halo_max, summary.halo_bytes_per_pass);
    }
    // The owners are balanced whatever the input partition.
    EXPECT_LE(summary.owned_max - summary.owned_min, house().cloud.size() / 100 + 1) << name;
  }
}

TEST(MpiFilter, StopRuleAndRadiiMatchOneProcess) {
  PointCloud cloud = house().cloud;
  cloud.radii.assign(cloud.size(), 0.0);
  for (std::size_t i = 0; i < cloud.size(); ++i) cloud.radii[i] = house().spacing * (0.9 + 0.2 * double(i % 7) / 6);
  FilterParams params;
  params.iterations = 12;
  params.stop_change_deg = 0.5;
  const FilterResult expected = one_process(cloud, params, reference_options());
  const Comparison c = compare(cloud, even, params, reference_options(), expected);
  EXPECT_TRUE(c.identical) << "largest angle " << c.max_deg << " deg";
}

TEST(MpiFilter, OpenClMatchesOneProcess) {
  std::string why;
  if (no_opencl_device(why)) GTEST_SKIP() << why;
  FilterOptions options;  // PNF_DEVICE, else the default rule: PoCL here
  FilterParams params;
  params.iterations = 2;
  const FilterResult expected = one_process(house().cloud, params, options);
  const Comparison c = compare(house().cloud, even, params, options, expected);
  EXPECT_TRUE(c.identical) << "largest angle " << c.max_deg << " deg";
}

// One stray point far from the house: the origin every rank re-centres on is one process's (the
// medians of the spacing samples, gathered from the ranks), so the floats and normals are one
// process's, bit for bit, and the stray point moves no other normal (NormalFilterTest.
// AFarPointLeavesTheOthersAsTheyWere for one process).
TEST(MpiFilter, AFarPointMatchesOneProcess) {
  std::string why;
  if (no_opencl_device(why)) GTEST_SKIP() << why;
  FilterOptions options;  // PNF_DEVICE, else the default rule: PoCL here
  PointCloud cloud = house().cloud;
  cloud.positions.push_back({-1e7, 3e6, 5});
  cloud.normals.push_back({0, 0, 1});
  FilterParams params;
  params.iterations = 2;
  const FilterResult expected = one_process(cloud, params, options);
  for (const auto& [name, split] : {std::pair<const char*, Split>{"even", even}, {"uneven", uneven}}) {
    const Comparison c = compare(cloud, split, params, options, expected);
    EXPECT_TRUE(c.identical) << name << ": largest angle " << c.max_deg << " deg";
  }
}

// A stray point 1e10 away stretches the cloud's box, not the halos: each rank holds about the
// halo it holds without it (the grid's cells were widened by a billionth of the box, 10 units:
// at 2 ranks 4745 halo points instead of 3626; 3773 now, the partition moved by the point).
TEST(MpiFilter, AFarPointLeavesTheHalosAsTheyWere) {
  FilterParams params;
  params.iterations = 1;
  auto halo_max = [&](const PointCloud& cloud) {
    const std::vector<std::size_t> first = even(cloud.size(), ranks());
    const PointCloud part = slice(cloud, first[std::size_t(rank())], first[std::size_t(rank()) + 1]);
    std::vector<Vec3> normals(part.size());
    return mpi::improve_normals(MPI_COMM_WORLD, CloudView(part), MutableVec3ArrayView(normals), params,
                                reference_options())
        .halo_max;
  };
  PointCloud cloud = house().cloud;
  const std::size_t alone = halo_max(cloud);
  cloud.positions.push_back({1e10, -2e9, 7});
  cloud.normals.push_back({0, 0, 1});
  EXPECT_LE(halo_max(cloud), alone + alone / 10 + 1) << "without the far point: " << alone;
}

// The curve's frame across ranks is one process's, on every partition: where the sample is a
// hashed subset (over 2^17 points) and a far point makes the frame the bulk's.
TEST(MpiPartition, CurveFrameIsOneProcesses) {
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-1, 1);
  PointCloud cloud;
  for (int i = 0; i < 200000; ++i) cloud.positions.push_back({u(rng), 2 * u(rng), u(rng)});
  cloud.positions[12345] = {4e8, -3e8, 1e3};
  const pnf::detail::MortonFrame expected = pnf::detail::morton_frame_of(Vec3ArrayView(cloud.positions));
  const BoundingBox box = bounding_box(Vec3ArrayView(cloud.positions));
  ASSERT_NE(expected.to_cells, pnf::detail::morton_frame(box.min, box.max, {}).to_cells) << "the bulk's frame";
  for (const auto& [name, split] : {std::pair<const char*, Split>{"even", even},
                                    {"uneven", uneven},
                                    {"all on last", all_on_last},
                                    {"one empty", one_empty}}) {
    const std::vector<std::size_t> first = split(cloud.size(), ranks());
    const PointCloud part = slice(cloud, first[std::size_t(rank())], first[std::size_t(rank()) + 1]);
    const mpi::detail::GlobalFrame frame = mpi::detail::global_frame(MPI_COMM_WORLD, Vec3ArrayView(part.positions));
    EXPECT_EQ(frame.morton.low, expected.low) << name;
    EXPECT_EQ(frame.morton.to_cells, expected.to_cells) << name;
  }
}

TEST(MpiFilter, HalosCoveringTheWholeCloud) {
  const SyntheticCloud small = make_scanned_house(1500);
  FilterParams params;
  params.sigma_f = 200;  // 2 sigma_f spans the house twice: every rank's halo is every other point
  params.iterations = 2;
  const FilterResult expected = one_process(small.cloud, params, reference_options());
  mpi::DistributedSummary summary;
  const Comparison c = compare(small.cloud, even, params, reference_options(), expected, &summary);
  EXPECT_TRUE(c.identical) << "largest angle " << c.max_deg << " deg";
  // Every rank holds the whole cloud: its own points and all the others.
  EXPECT_EQ(summary.halo_min + summary.owned_max, small.cloud.size());
  EXPECT_EQ(summary.halo_max + summary.owned_min, small.cloud.size());
}

TEST(MpiFilter, TooFewPointsMeetTheOneProcessRefusal) {
  const PointCloud cloud = slice(house().cloud, 0, 3);
  std::string one;
  try {
    improve_normals(cloud, FilterParams{}, reference_options());
  } catch (const Error& e) {
    one = e.what();
  }
  ASSERT_FALSE(one.empty());
  const std::vector<std::size_t> first = even(cloud.size(), ranks());
  const PointCloud part = slice(cloud, first[std::size_t(rank())], first[std::size_t(rank()) + 1]);
  std::vector<Vec3> normals(part.size());
  try {
    mpi::improve_normals(MPI_COMM_WORLD, part, normals, FilterParams{}, reference_options());
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_input);
    EXPECT_NE(std::string(e.what()).find(one), std::string::npos) << e.what();
  }
}

TEST(MpiFilter, EmptyCloudEverywhere) {
  std::vector<Vec3> normals;
  const mpi::DistributedSummary s =
      mpi::improve_normals(MPI_COMM_WORLD, PointCloud{}, normals, FilterParams{}, reference_options());
  EXPECT_EQ(s.points, 0u);
}

// A bad point on the last rank ends the run on every rank with one message naming that rank.
TEST(MpiFilter, FailingRankEndsTheRunEverywhere) {
  const std::vector<std::size_t> first = even(house().cloud.size(), ranks());
  PointCloud part = slice(house().cloud, first[std::size_t(rank())], first[std::size_t(rank()) + 1]);
  if (rank() == ranks() - 1) part.positions[5][1] = std::nan("");
  std::vector<Vec3> normals(part.size(), Vec3{9, 9, 9});
  const std::string who = "rank " + std::to_string(ranks() - 1) + " of " + std::to_string(ranks()) + ": ";
  try {
    mpi::improve_normals(MPI_COMM_WORLD, part, normals, FilterParams{}, reference_options());
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_input);
    EXPECT_EQ(std::string(e.what()).rfind(who, 0), 0u) << e.what();
  }
  for (const Vec3& n : normals) ASSERT_EQ(n, (Vec3{9, 9, 9})) << "normals written after a failure";
}

// A device that fails on one rank only (a selector that matches nothing).
TEST(MpiFilter, DeviceErrorOnOneRank) {
  const std::vector<std::size_t> first = even(house().cloud.size(), ranks());
  const PointCloud part = slice(house().cloud, first[std::size_t(rank())], first[std::size_t(rank()) + 1]);
  FilterOptions options = reference_options();
  if (rank() == ranks() - 1) options.device = Device::opencl("no-such-device-anywhere");
  std::vector<Vec3> normals(part.size());
  try {
    mpi::improve_normals(MPI_COMM_WORLD, part, normals, FilterParams{}, options);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::device);
    EXPECT_NE(std::string(e.what()).find("rank " + std::to_string(ranks() - 1)), std::string::npos) << e.what();
  }
}

// --auto across the ranks, each a slice of `cloud` (even and uneven), against one process's run
// `one` with its normals `expected`: the same rule, judged scores, setting and passes kept, and
// the same normals, bit for bit.
void expect_auto_as_one_process(const PointCloud& cloud, const AutoRun& one, const std::vector<Vec3>& expected) {
  for (const Split& split : {Split(even), Split(uneven)}) {
    const std::vector<std::size_t> first = split(cloud.size(), ranks());
    const std::size_t begin = first[std::size_t(rank())], end = first[std::size_t(rank()) + 1];
    const PointCloud part = slice(cloud, begin, end);
    std::vector<Vec3> normals(part.size());
    const mpi::DistributedAutoRun run =
        mpi::improve_normals_auto(MPI_COMM_WORLD, CloudView(part), MutableVec3ArrayView(normals), reference_options());
    EXPECT_EQ(run.choice.rule, one.choice.rule);
    EXPECT_EQ(run.choice.judged, one.choice.judged);
    EXPECT_EQ(run.passes_kept, one.passes_kept);
    EXPECT_EQ(run.choice.params.sigma_f, one.choice.params.sigma_f);
    EXPECT_EQ(run.choice.params.sigma_g, one.choice.params.sigma_g);
    // Every rank's estimate is rank 0's (broadcast): Stein's noise among it.
    EXPECT_EQ(run.choice.estimate.normal_noise_neighbours_deg, one.choice.estimate.normal_noise_neighbours_deg);
    EXPECT_EQ(run.choice.estimate.normal_noise_chords_deg, one.choice.estimate.normal_noise_chords_deg);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < part.size(); ++i) differ += normals[i] != expected[begin + i];
    EXPECT_EQ(differ, 0u) << "normals not one process's";
  }
}

}  // namespace

// --auto across the ranks is one process's --auto on the concatenation of the ranks' rows: the
// same estimate, rule, judged scores and passes, and the same normals, bit for bit, for any
// partition, here of the house with its rows in random order.
TEST(MpiAuto, ChoosesJudgesAndFiltersAsOneProcess) {
  PointCloud cloud = house().cloud;
  std::vector<std::size_t> order(cloud.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::shuffle(order.begin(), order.end(), std::mt19937(5));
  PointCloud shuffled;
  for (std::size_t i : order) {
    shuffled.positions.push_back(cloud.positions[i]);
    shuffled.normals.push_back(cloud.normals[i]);
  }
  NormalFilter filter(reference_options());
  std::vector<Vec3> expected(shuffled.size());
  const AutoRun one = improve_normals_auto(CloudView(shuffled), MutableVec3ArrayView(expected), filter);
  ASSERT_FALSE(one.choice.judged.empty());
  // The house's tilted normals have independent errors: Stein's estimate decides, so its probed
  // runs (each rank nudging its own rows) are checked against one process's too.
  EXPECT_NE(one.choice.judged.find("Stein's risk estimate"), std::string::npos) << one.choice.judged;
  expect_auto_as_one_process(shuffled, one, expected);
}

namespace {

// `cloud` with PCA normals over `k` points, run by one process's --auto, whose judged text must
// hold `judged_part`; then run across the ranks.
void expect_pca_normals_as_one_process(PointCloud cloud, int k, const std::string& judged_part) {
  EstimateParams pca;
  pca.k = k;
  pca.orientation = Orientation::outward;
  cloud.normals = estimate_normals(cloud.positions, pca);
  NormalFilter filter(reference_options());
  std::vector<Vec3> expected(cloud.size());
  const AutoRun one = improve_normals_auto(CloudView(cloud), MutableVec3ArrayView(expected), filter);
  ASSERT_NE(one.choice.judged.find(judged_part), std::string::npos) << one.choice.judged;
  expect_auto_as_one_process(cloud, one, expected);
}

// The house (`points` points, `position_noise` spacings of noise) with PCA normals over `k` points.
void expect_house_with_pca_normals_as_one_process(double position_noise, int k, const std::string& judged_part,
                                                  std::size_t points = 6000) {
  ScanNoise noise;
  noise.position = position_noise;
  expect_pca_normals_as_one_process(make_scanned_house(points, noise).cloud, k, judged_part);
}

}  // namespace

// The same where the judged settings keep the input and the fallback's one wide pass is judged
// (the noisy house with PCA-16 normals: lib/src/auto/judged_passes.hpp, tries_fallback).
TEST(MpiAuto, JudgesTheNoisyFallbackAsOneProcess) {
  expect_house_with_pca_normals_as_one_process(0.5, 16, ": the fallback, 1 pass kept");
}

// The same where the judge's fits hold several passes' reach and the input normals are plane fits
// (the house at 0.8 spacings of noise with PCA-16 normals; 4000 points, which keep the sanitizer
// build's run short): the fallback runs the passes fallback_pass_budget allows (judged_passes.hpp),
// every rank judging them from rank 0's judge.
TEST(MpiAuto, JudgesTheFallbacksPassesAsOneProcess) {
  expect_house_with_pca_normals_as_one_process(0.8, 16, ": the fallback, 3 passes kept", 4000);
}

// The same where the noise hides the features (the house at 4 spacings with PCA-16 normals, 10000
// points, so that the judge's fits of 4097 hold under half of it): the rule's plain averaging is
// held to the passes the judge's fits reach (judged_pass_budget), from rank 0's broadcast fit count.
TEST(MpiAuto, HoldsPlainAveragingToTheJudgesFitsAsOneProcess) {
  expect_house_with_pca_normals_as_one_process(4.0, 16, "(its 14 passes held to 4, as many as the judge's fits reach)",
                                               10000);
}

// The same on clean positions, where the judge tries the smooth-detail setting after the rule's
// (lib/src/auto/judged_passes.hpp, tries_smooth_detail): its passes are judged against the best
// of the rule's, and end where one process's end.
TEST(MpiAuto, JudgesTheSecondSettingAsOneProcess) {
  expect_house_with_pca_normals_as_one_process(0, 16, "; sigma_f 2, sigma_g 0.5");
}

// The same where the input normals are PCA normals over 64 points and rank 0's judge fits half of
// them (SurfaceJudge::choose_scale, under_support): every rank is told the fits it scored with.
TEST(MpiAuto, JudgesUnderTheInputsSupportAsOneProcess) {
  expect_house_with_pca_normals_as_one_process(0, 64, "fits of 32 points, under the 64 whose plane the input follows");
}

// The held-out check on noisy positions (PCA-16 normals at two spacings of noise, where the judge's
// fits hold more than half the house and vouch for no pass: judged_passes.hpp,
// judge_fits_too_wide), its planes on rank 0 and its pass kept on every rank, as one process keeps it.
TEST(MpiAuto, JudgesTheHeldOutCheckAsOneProcess) {
  expect_house_with_pca_normals_as_one_process(2.0, 16, ": the held-out check's pass");
}

// The same where the judged settings keep the input and the input normals are PCA normals, plane
// fits of their nearest points (the ripples with PCA-16 normals): the narrow pass runs
// (judged_passes.hpp, tries_narrow_pass), told to every rank by rank 0's judge.
TEST(MpiAuto, JudgesTheNarrowPassAsOneProcess) {
  expect_pca_normals_as_one_process(test::rippled_grid(), 16,
                                    "; the input normals are plane fits of 16 points: narrow pass");
}

// The noisy house with its exact normals, whose own noise is under the judge's own error: no pass
// can be judged (judged_passes.hpp, judge_cannot_see_gains), on every rank from rank 0's judge.
TEST(MpiAuto, KeepsNormalsNoPassCanBeJudgedOnAsOneProcess) {
  ScanNoise noise;
  noise.position = 0.5;
  SyntheticCloud house = make_scanned_house(6000, noise);
  house.cloud.normals = house.true_normals;
  NormalFilter filter(reference_options());
  std::vector<Vec3> expected(house.cloud.size());
  const AutoRun one = improve_normals_auto(CloudView(house.cloud), MutableVec3ArrayView(expected), filter);
  ASSERT_NE(one.choice.judged.find("no pass could be judged"), std::string::npos) << one.choice.judged;
  expect_auto_as_one_process(house.cloud, one, expected);
}

// The noisy house with PCA-16 normals tilted by 5 degrees (no plane fits any more): the input's own
// noise puts a floor under the judge's error (judged_passes.hpp, judge_error_deg), which sets the
// bars; every rank weighs the same floor from rank 0's judge.
TEST(MpiAuto, JudgesWithTheFloorUnderTheJudgesErrorAsOneProcess) {
  ScanNoise noise;
  noise.position = 0.5;
  PointCloud cloud = make_scanned_house(6000, noise).cloud;
  EstimateParams pca;
  pca.k = 16;
  pca.orientation = Orientation::outward;
  cloud.normals = estimate_normals(cloud.positions, pca);
  std::mt19937 rng(7);
  for (Vec3& n : cloud.normals) n = test::jitter_normal(n, 5, rng);
  NormalFilter filter(reference_options());
  std::vector<Vec3> expected(cloud.size());
  const AutoRun one = improve_normals_auto(CloudView(cloud), MutableVec3ArrayView(expected), filter);
  ASSERT_NE(one.choice.judged.find("by the input normals' own noise"), std::string::npos) << one.choice.judged;
  ASSERT_GT(one.passes_kept, 0) << one.choice.judged;
  expect_auto_as_one_process(cloud, one, expected);
}

// The same house with its true normals tilted by 10 degrees (no plane fits, so no held-out check):
// the input kept without a pass on every rank, as one process keeps it.
TEST(MpiAuto, KeepsTheInputWhereTheJudgesFitsHoldHalfTheCloudAsOneProcess) {
  ScanNoise noise;
  noise.position = 2.0;
  SyntheticCloud house = make_scanned_house(6000, noise);
  std::mt19937 rng(7);
  for (std::size_t i = 0; i < house.true_normals.size(); ++i) {
    house.cloud.normals[i] = test::jitter_normal(house.true_normals[i], 10, rng);
  }
  NormalFilter filter(reference_options());
  std::vector<Vec3> expected(house.cloud.size());
  const AutoRun one = improve_normals_auto(CloudView(house.cloud), MutableVec3ArrayView(expected), filter);
  ASSERT_NE(one.choice.judged.find("more than half of the"), std::string::npos) << one.choice.judged;
  expect_auto_as_one_process(house.cloud, one, expected);
}

// Points on a line cannot be estimated on any rank: every rank ends with the cause (the one
// process's estimate_data message) rather than a bare "too few points", also when the failing
// slices are not rank 0's.
TEST(MpiAuto, UnestimableCloudIsRefusedWithItsCause) {
  PointCloud cloud;
  for (int i = 0; i < 3000; ++i) {
    cloud.positions.push_back({0.001 * i, 0, 0});
    cloud.normals.push_back({0, 0, 1});
  }
  // One process's refusal, which every rank then gives (rank 0 estimates the whole cloud).
  std::string one_process;
  try {
    choose_filter_params(CloudView(cloud));
  } catch (const Error& e) {
    one_process = e.what();
  }
  ASSERT_NE(one_process.find("on a line"), std::string::npos) << one_process;
  for (const Split& split : {Split(even), Split(all_on_last)}) {
    const std::vector<std::size_t> first = split(cloud.size(), ranks());
    const PointCloud part = slice(cloud, first[std::size_t(rank())], first[std::size_t(rank()) + 1]);
    try {
      mpi::choose_filter_params(MPI_COMM_WORLD, CloudView(part));
      ADD_FAILURE() << "points on a line were estimated";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::invalid_input) << e.what();
      EXPECT_NE(std::string(e.what()).find(one_process), std::string::npos) << e.what();
    }
  }
}

// A cloud without normals is refused by --auto across the ranks as by one process (it once
// crashed the judge on rank 0), on every rank.
TEST(MpiAuto, CloudWithoutNormalsIsRefusedAsByOneProcess) {
  PointCloud cloud = house().cloud;
  cloud.normals.clear();
  const std::vector<std::size_t> first = even(cloud.size(), ranks());
  const PointCloud part = slice(cloud, first[std::size_t(rank())], first[std::size_t(rank()) + 1]);
  std::vector<Vec3> normals(part.size());
  try {
    mpi::improve_normals_auto(MPI_COMM_WORLD, CloudView(part), MutableVec3ArrayView(normals), reference_options());
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_input) << e.what();
    EXPECT_NE(std::string(e.what()).find("improve_normals_auto: the cloud has no normals"), std::string::npos)
        << e.what();
  }
}

int main(int argc, char** argv) {
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  ::testing::InitGoogleTest(&argc, argv);
  const int result = RUN_ALL_TESTS();
  MPI_Finalize();
  return result;
}
