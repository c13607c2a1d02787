#include "spatial/spatial_index.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <random>
#include <set>
#include <stdexcept>
#include <thread>

#include "pnf/bounding_box.hpp"
#include "pnf/error.hpp"

#include "spatial/spatial_order.hpp"

namespace {

using pnf::detail::CsrLists;
using pnf::detail::SpatialIndex;

std::vector<double> random_points(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> p(3 * n);
  for (double& v : p) v = u(rng);
  return p;
}

std::set<std::uint32_t> brute_force(const std::vector<double>& p, std::size_t s, double radius) {
  std::set<std::uint32_t> out;
  for (std::size_t j = 0; j < p.size() / 3; ++j) {
    double d2 = 0;
    for (int k = 0; k < 3; ++k) d2 += (p[3 * j + k] - p[3 * s + k]) * (p[3 * j + k] - p[3 * s + k]);
    if (std::sqrt(d2) <= radius) out.insert(static_cast<std::uint32_t>(j));
  }
  return out;
}

TEST(SpatialIndex, MatchBruteForce) {
  std::vector<double> p = random_points(2000, 1);
  SpatialIndex search(p);
  const double radius = 0.08;
  std::vector<std::uint32_t> counts = search.count_within(radius);
  CsrLists lists = search.lists_within(radius, 0, 2000, counts);
  ASSERT_EQ(lists.offsets.size(), 2001u);
  for (std::size_t s = 0; s < 2000; ++s) {
    std::set<std::uint32_t> got(lists.indices.begin() + lists.offsets[s], lists.indices.begin() + lists.offsets[s + 1]);
    EXPECT_EQ(got.size(), lists.offsets[s + 1] - lists.offsets[s]) << "duplicate ids in list " << s;
    EXPECT_EQ(got, brute_force(p, s, radius)) << "point " << s;
    EXPECT_TRUE(got.count(static_cast<std::uint32_t>(s))) << "point " << s << " is not its own neighbour";
  }
}

// The list searches ask their poll on the calling thread only, with a share done that grows
// within [0, 1], and a false answer stops them with Error(cancelled). The lists a poll watched are
// the lists without one.
TEST(SpatialIndex, SearchesReportOnTheCallingThreadAndCancel) {
  std::vector<double> p = random_points(20000, 5);
  SpatialIndex search(p);
  const double radius = 0.05;
  const std::thread::id caller = std::this_thread::get_id();
  std::vector<double> seen;
  bool other_thread = false;
  const pnf::detail::WorkPoll watch = [&](double fraction) {
    other_thread = other_thread || std::this_thread::get_id() != caller;
    seen.push_back(fraction);
    return true;
  };
  const std::vector<std::uint32_t> counts = search.count_within(radius, 0, 20000, watch);
  EXPECT_EQ(counts, search.count_within(radius));
  ASSERT_FALSE(seen.empty());  // the first block always asks
  EXPECT_FALSE(other_thread);
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  EXPECT_GE(seen.front(), 0.0);
  EXPECT_LE(seen.back(), 1.0);
  seen.clear();
  const CsrLists watched = search.lists_within(radius, 0, 20000, counts, watch);
  EXPECT_EQ(watched.indices, search.lists_within(radius, 0, 20000, counts).indices);
  EXPECT_FALSE(seen.empty());
  EXPECT_FALSE(other_thread);
  seen.clear();
  search.nearest_table(8, watch);
  EXPECT_FALSE(seen.empty());
  EXPECT_FALSE(other_thread);

  const pnf::detail::WorkPoll cancel = [](double) { return false; };
  const auto expect_cancelled = [](const std::function<void()>& body, const char* what) {
    try {
      body();
      ADD_FAILURE() << what << " was not cancelled";
    } catch (const pnf::Error& e) {
      EXPECT_EQ(e.code(), pnf::ErrorCode::cancelled) << what << ": " << e.what();
    }
  };
  expect_cancelled([&] { search.count_within(radius, 0, 20000, cancel); }, "count_within");
  expect_cancelled([&] { search.lists_within(radius, 0, 20000, counts, cancel); }, "lists_within");
  expect_cancelled([&] { search.nearest_table(8, cancel); }, "nearest_table");
  // An exception thrown by the poll stops the workers and comes back as it was.
  EXPECT_THROW(search.count_within(radius, 0, 20000, [](double) -> bool { throw std::logic_error("from poll"); }),
               std::logic_error);
}

// Every scan variant (plain, target_clones, explicit AVX-512 and AVX2, other block sizes) gives the lists
// of brute force, on an integer grid where many neighbours sit exactly on the radius (distances
// of integer points are exact in double, so the inclusive test decides them) and each point has
// far more than 16 candidates (the AVX-512 scans' step).
TEST(SpatialIndex, EveryScanVariantGivesTheBruteForceLists) {
  std::vector<double> p;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      for (int k = 0; k < 10; ++k) p.insert(p.end(), {double(i) - 4.5, double(j) - 4.5, double(k) - 4.5});
  const std::size_t n = p.size() / 3;
  const double radius = 3.0;  // (3,0,0), (2,2,1) and their images lie exactly on it
  SpatialIndex search(p);
  std::vector<SpatialIndex::ListTuning> tunings(6);
  tunings[1].avx512_scan = false;  // explicit AVX2 (where the CPU has it)
  tunings[2].avx512_scan = false;  // target_clones count, plain fill
  tunings[2].avx2_scan = false;
  tunings[3].avx512_scan = false;  // plain
  tunings[3].avx2_scan = false;
  tunings[3].wide_scan = false;
  tunings[4].block_extent_in_radii = 0.5;
  tunings[5].block_extent_in_radii = 1.5;
  for (std::size_t t = 0; t < tunings.size(); ++t) {
    search.set_list_tuning(tunings[t]);
    const std::vector<std::uint32_t> counts = search.count_within(radius);
    const CsrLists lists = search.lists_within(radius, 0, n, counts);
    for (std::size_t s = 0; s < n; ++s) {
      const std::set<std::uint32_t> want = brute_force(p, s, radius);
      ASSERT_EQ(counts[s], want.size()) << "tuning " << t << ", point " << s;
      const std::vector<std::uint32_t> got(lists.indices.begin() + lists.offsets[s],
                                           lists.indices.begin() + lists.offsets[s + 1]);
      ASSERT_EQ(got, std::vector<std::uint32_t>(want.begin(), want.end())) << "tuning " << t << ", point " << s;
    }
  }
}

// Every scan variant rounds the squared distance as the plain expression does, unfused: neighbours
// placed exactly on the radius by that expression, where a fused multiply-add would put them
// just outside, are in every variant's lists. (GCC fused the AVX-512 scans' products into FMAs
// until the library was built with -ffp-contract=off; then the same cloud could have other lists
// on another CPU.)
TEST(SpatialIndex, EveryScanVariantRoundsTheDistanceUnfused) {
  const std::vector<double> p = random_points(300, 11);
  const std::size_t n = p.size() / 3;
  SpatialIndex search(p);
  std::vector<SpatialIndex::ListTuning> tunings(4);
  tunings[1].avx512_scan = false;
  tunings[2].avx512_scan = false;
  tunings[2].avx2_scan = false;
  tunings[3].avx512_scan = false;
  tunings[3].avx2_scan = false;
  tunings[3].wide_scan = false;
  int cases = 0;
  for (std::size_t s = 0; s < n && cases < 40; ++s) {
    for (std::size_t j = 0; j < n && cases < 40; ++j) {
      const double dx = p[3 * j] - p[3 * s], dy = p[3 * j + 1] - p[3 * s + 1], dz = p[3 * j + 2] - p[3 * s + 2];
      const double d2 = dx * dx + dy * dy + dz * dz;
      const double radius = std::sqrt(d2);
      // On the radius exactly, and outside it by some fused rounding of the same sum.
      const double fused[] = {std::fma(dz, dz, std::fma(dy, dy, dx * dx)), std::fma(dz, dz, dx * dx + dy * dy),
                              std::fma(dx, dx, dy * dy) + dz * dz};
      if (j == s || radius * radius != d2 || !(std::max({fused[0], fused[1], fused[2]}) > d2)) continue;
      ++cases;
      for (std::size_t t = 0; t < tunings.size(); ++t) {
        search.set_list_tuning(tunings[t]);
        const std::vector<std::uint32_t> counts = search.count_within(radius);
        const CsrLists lists = search.lists_within(radius, s, 1, counts);
        EXPECT_EQ(counts[s], lists.indices.size()) << "tuning " << t;
        const std::vector<std::uint32_t> got(lists.indices.begin(), lists.indices.end());
        EXPECT_TRUE(std::count(got.begin(), got.end(), std::uint32_t(j)) == 1)
            << "tuning " << t << ": point " << j << " on the radius of point " << s;
      }
    }
  }
  EXPECT_EQ(cases, 40);
}

// Candidates kept by the count give the fill the same lists, for the whole range and for a chunk
// inside it; they do not claim to cover another radius or a range outside the count's.
TEST(SpatialIndex, KeptCandidatesGiveTheSameLists) {
  std::vector<double> p = random_points(5000, 3);
  SpatialIndex search(p);
  const double radius = 0.07;
  pnf::detail::BlockCandidates kept;
  const std::vector<std::uint32_t> counts = search.count_within(radius, 0, 5000, {}, &kept);
  EXPECT_EQ(counts, search.count_within(radius));
  ASSERT_TRUE(kept.covers(radius, 0, 5000));
  EXPECT_FALSE(kept.covers(radius * 1.01, 0, 5000));
  EXPECT_GT(kept.bytes(), 0u);
  for (const auto& [first, count] : {std::pair<std::size_t, std::size_t>{0, 5000}, {1234, 2000}}) {
    std::vector<std::uint32_t> sub(counts.begin(), counts.end());
    const CsrLists want = search.lists_within(radius, first, count, sub);
    std::vector<std::uint64_t> offsets(count + 1);
    std::vector<std::uint32_t> indices(want.indices.size());
    search.fill_lists(radius, first, count, counts, offsets.data(), indices.data(), {}, &kept);
    EXPECT_EQ(indices, want.indices) << "chunk at " << first;
    EXPECT_EQ(offsets, want.offsets) << "chunk at " << first;
  }
  pnf::detail::BlockCandidates part;
  search.count_within(radius, 1000, 1000, {}, &part);
  EXPECT_TRUE(part.covers(radius, 1200, 500));
  EXPECT_FALSE(part.covers(radius, 500, 1000));
}

TEST(SpatialIndex, RadiusIsInclusive) {
  // Integer grid, radius exactly 1: the 6 axis neighbours sit exactly on the boundary and belong.
  std::vector<double> p;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) p.insert(p.end(), {double(i), double(j), double(k)});
  SpatialIndex search(p);
  std::vector<std::uint32_t> counts = search.count_within(1.0);
  EXPECT_EQ(counts[13], 7u);  // the centre (1,1,1): itself and 6 at distance 1
  EXPECT_EQ(counts[0], 4u);   // a corner: itself and 3
}

TEST(SpatialIndex, ChunkListsEqualTheWholeCloudsLists) {
  std::vector<double> p = random_points(1000, 2);
  SpatialIndex search(p);
  std::vector<std::uint32_t> counts = search.count_within(0.1);
  CsrLists whole = search.lists_within(0.1, 0, 1000, counts);
  CsrLists part = search.lists_within(0.1, 400, 300, counts);
  ASSERT_EQ(part.offsets.size(), 301u);
  EXPECT_EQ(part.offsets[0], 0u);
  for (std::size_t k = 0; k < 300; ++k) {
    std::vector<std::uint32_t> a(whole.indices.begin() + whole.offsets[400 + k],
                                 whole.indices.begin() + whole.offsets[401 + k]);
    std::vector<std::uint32_t> b(part.indices.begin() + part.offsets[k], part.indices.begin() + part.offsets[k + 1]);
    EXPECT_EQ(a, b) << "point " << 400 + k;
  }
}

TEST(SpatialIndex, MeanKnnDistanceOnAGrid) {
  std::vector<double> p;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) p.insert(p.end(), {0.5 * i, 0.5 * j, 0.0});
  SpatialIndex search(p);
  std::vector<double> d = search.mean_knn_distance(4, 400);
  ASSERT_EQ(d.size(), 400u);
  EXPECT_NEAR(d[21 * 10], 0.5, 1e-12);  // an interior point: 4 edge neighbours at 0.5
}

// Squared distances from point s to every other point, nearest first (random points: no ties).
std::vector<std::pair<double, std::uint32_t>> brute_force_nearest(const std::vector<double>& p, std::size_t s) {
  std::vector<std::pair<double, std::uint32_t>> out;
  for (std::size_t j = 0; j < p.size() / 3; ++j) {
    double d2 = 0;
    for (int k = 0; k < 3; ++k) d2 += (p[3 * j + k] - p[3 * s + k]) * (p[3 * j + k] - p[3 * s + k]);
    out.push_back({d2, static_cast<std::uint32_t>(j)});
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(SpatialIndex, NearestTableMatchesBruteForce) {
  std::vector<double> p = random_points(1500, 3);
  const SpatialIndex index(p);
  const int k = 8;
  const pnf::detail::NeighbourTable table = index.nearest_table(k);
  ASSERT_EQ(table.point_count, 1500u);
  ASSERT_EQ(table.k, k);
  for (std::size_t s = 0; s < 1500; s += 7) {
    const auto truth = brute_force_nearest(p, s);  // truth[0] is s itself
    for (int slot = 0; slot < k; ++slot) {
      EXPECT_EQ(std::uint32_t(table.row(s)[slot]), truth[std::size_t(slot) + 1].second)
          << "point " << s << " slot " << slot;
    }
  }
}

// FLANN's sorted array (up to 250 neighbours) and, from 250, the search within a radius that
// holds k give the exact k nearest: in a volume, on a plane (where the guessed radius is sized),
// along a line (which needs it widened) and among duplicates (no radius to widen: FLANN's own).
// Ties may come back in any order, so the distances are compared, and each id's own distance
// (to 1e-12: FLANN sums the squares in its own order).
TEST(SpatialIndex, NearestOfPointMatchesBruteForce) {
  std::vector<std::vector<double>> clouds = {random_points(2000, 4), random_points(2000, 6), random_points(2000, 7),
                                             random_points(2000, 8)};
  for (std::size_t i = 0; i < 2000; ++i) {
    clouds[1][3 * i + 2] = 0;
    clouds[2][3 * i + 1] *= 1e-3;
    clouds[2][3 * i + 2] *= 1e-3;
    if (i < 400) std::copy(&clouds[3][0], &clouds[3][3], &clouds[3][3 * i]);  // 400 points at point 0
  }
  for (std::size_t c = 0; c < clouds.size(); ++c) {
    const SpatialIndex index(clouds[c], SpatialIndex::Layout::any_order);
    for (std::size_t k : {std::size_t(5), std::size_t(300), std::size_t(1200)}) {
      std::vector<std::size_t> ids(k);
      std::vector<double> squared(k);
      for (std::size_t s = 0; s < 2000; s += 101) {
        index.nearest_of_point(s, k, ids.data(), squared.data());
        const auto truth = brute_force_nearest(clouds[c], s);
        std::vector<double> by_id(2000);
        for (const auto& [d2, id] : truth) by_id[id] = d2;
        std::vector<double> got = squared;
        std::sort(got.begin(), got.end());
        for (std::size_t j = 0; j < k; ++j) {
          EXPECT_NEAR(got[j], truth[j].first, 1e-12)
              << "cloud " << c << ", point " << s << ", k " << k << ", rank " << j;
          EXPECT_NEAR(squared[j], by_id[ids[j]], 1e-12) << "cloud " << c << ", id " << ids[j] << "'s distance";
        }
        EXPECT_EQ(std::set<std::size_t>(ids.begin(), ids.end()).size(), k) << "cloud " << c << ": repeated ids";
      }
    }
  }
}

TEST(SpatialIndex, LayoutChangesNoAnswer) {
  std::vector<double> p = random_points(3000, 6);
  const SpatialIndex in_place(p, SpatialIndex::Layout::curve_ordered);
  const SpatialIndex copied(p, SpatialIndex::Layout::any_order);
  const std::vector<std::uint32_t> counts = in_place.count_within(0.07);
  EXPECT_EQ(counts, copied.count_within(0.07));
  const CsrLists a = in_place.lists_within(0.07, 0, 3000, counts), b = copied.lists_within(0.07, 0, 3000, counts);
  EXPECT_EQ(a.offsets, b.offsets);
  EXPECT_EQ(a.indices, b.indices);
  EXPECT_EQ(in_place.nearest_table(6).indices, copied.nearest_table(6).indices);
  EXPECT_EQ(in_place.mean_knn_distance(4, 3000), copied.mean_knn_distance(4, 3000));
}

// The mean distance of one point does not depend on where the tree holds it: sampling a shuffled
// copy through the permutation gives the same values bit for bit.
TEST(SpatialIndex, MeanKnnDistanceThroughAnOrderIsOrderFree) {
  std::vector<double> p = random_points(2000, 8);
  std::vector<std::uint32_t> shuffle(2000);
  std::iota(shuffle.begin(), shuffle.end(), 0u);
  std::shuffle(shuffle.begin(), shuffle.end(), std::mt19937(3));
  std::vector<double> q(p.size());
  for (std::size_t i = 0; i < 2000; ++i)
    for (int k = 0; k < 3; ++k) q[3 * i + k] = p[3 * shuffle[i] + k];
  // q[i] = p[shuffle[i]], so point j of p is point inverse[j] of q.
  std::vector<std::uint32_t> inverse(2000);
  for (std::uint32_t i = 0; i < 2000; ++i) inverse[shuffle[i]] = i;
  const SpatialIndex original(p), shuffled(q, SpatialIndex::Layout::any_order);
  EXPECT_EQ(original.mean_knn_distance(4, 500), shuffled.mean_knn_distance(4, 500, &inverse));
}

TEST(SpatialOrder, IsAPermutationThatKeepsNeighboursClose) {
  std::vector<pnf::Vec3> points;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 5000; ++i) points.push_back({u(rng), u(rng), u(rng)});
  std::vector<std::uint32_t> order = pnf::detail::morton_order(points);
  std::vector<std::uint32_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (std::uint32_t i = 0; i < 5000; ++i) ASSERT_EQ(sorted[i], i);
  // Consecutive points along the curve are much closer than consecutive input points (random).
  auto mean_step = [&](auto index) {
    double sum = 0;
    for (int k = 1; k < 5000; ++k) {
      const pnf::Vec3 &a = points[index(k - 1)], &b = points[index(k)];
      sum += std::sqrt(std::pow(a[0] - b[0], 2) + std::pow(a[1] - b[1], 2) + std::pow(a[2] - b[2], 2));
    }
    return sum / 4999;
  };
  double curve = mean_step([&](int k) { return order[k]; });
  double input = mean_step([&](int k) { return k; });
  EXPECT_LT(curve, 0.25 * input);
}

// Nearest first, equal distances by rank, whatever the sort (a comparison sort for few
// neighbours, a radix sort for many): against std::sort by (distance, rank), with many ties.
TEST(SpatialOrder, SortNeighboursOrdersByDistanceThenRank) {
  std::mt19937 rng(9);
  for (std::size_t k : {5, 127, 128, 300, 4097}) {
    std::vector<std::uint32_t> rank(20000);
    std::iota(rank.begin(), rank.end(), 0u);
    std::shuffle(rank.begin(), rank.end(), rng);
    std::vector<std::size_t> ids(k);
    std::vector<double> distances(k);
    std::uniform_int_distribution<std::size_t> id(0, rank.size() - 1);
    std::uniform_int_distribution<int> level(0, int(k / 4));  // about four points a distance
    for (std::size_t j = 0; j < k; ++j) {
      ids[j] = id(rng);
      distances[j] = j % 7 == 0 ? 0.0 : std::ldexp(1.0 + level(rng) * 1e-3, level(rng) % 40 - 20);
    }
    std::vector<std::size_t> want(k);
    std::iota(want.begin(), want.end(), std::size_t{0});
    std::sort(want.begin(), want.end(), [&](std::size_t a, std::size_t b) {
      return distances[a] != distances[b] ? distances[a] < distances[b] : rank[ids[a]] < rank[ids[b]];
    });
    std::vector<std::size_t> sorted_ids = ids;
    std::vector<double> sorted_distances = distances;
    pnf::detail::sort_neighbours(sorted_ids.data(), sorted_distances.data(), k, rank);
    for (std::size_t j = 0; j < k; ++j) {
      ASSERT_EQ(sorted_distances[j], distances[want[j]]) << k << " " << j;
      ASSERT_EQ(rank[sorted_ids[j]], rank[ids[want[j]]]) << k << " " << j;
    }
  }
}

// One far point (a stray return, a (0, 0, 0) row among georeferenced points) made the curve's
// box a billion times the cloud's: every other point fell into one cell and the curve ordered
// them along x alone. The frame is now the bulk's: consecutive points along the curve stay as
// close as without the far point.
TEST(SpatialOrder, AFarPointLeavesTheOthersCloseAlongTheCurve) {
  std::mt19937 rng(6);
  std::normal_distribution<double> g(0, 1);
  const pnf::Vec3 place = {5.1e5, 4.2e6, 120};  // metres, as a georeferenced scan
  std::vector<pnf::Vec3> points;
  for (int i = 0; i < 20000; ++i) {
    pnf::Vec3 d = {g(rng), g(rng), g(rng)};
    const double r = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    points.push_back({place[0] + 10 * d[0] / r, place[1] + 10 * d[1] / r, place[2] + 10 * d[2] / r});
  }
  // The mean step between consecutive points along the curve of `cloud`, steps to or from the far
  // point left out.
  auto mean_step = [&](const std::vector<pnf::Vec3>& cloud) {
    const std::vector<std::uint32_t> order = pnf::detail::morton_order(cloud);
    double sum = 0;
    int steps = 0;
    for (std::size_t k = 1; k < order.size(); ++k) {
      if (order[k - 1] >= points.size() || order[k] >= points.size()) continue;
      const pnf::Vec3 &a = cloud[order[k - 1]], &b = cloud[order[k]];
      sum += std::sqrt(std::pow(a[0] - b[0], 2) + std::pow(a[1] - b[1], 2) + std::pow(a[2] - b[2], 2));
      ++steps;
    }
    return sum / steps;
  };
  const double alone = mean_step(points);
  for (const pnf::Vec3& far : {pnf::Vec3{0, 0, 0}, pnf::Vec3{-1e9, 0, 3e8}, pnf::Vec3{5.1e5, 4.2e6, 1e12}}) {
    std::vector<pnf::Vec3> with_far = points;
    with_far.push_back(far);
    EXPECT_LT(mean_step(with_far), 1.2 * alone) << far[0] << " " << far[1] << " " << far[2];
  }
  // A cloud without far points keeps its box's frame, and so the curve it always had.
  const pnf::BoundingBox box = pnf::bounding_box(pnf::Vec3ArrayView(points));
  const pnf::detail::MortonFrame own = pnf::detail::morton_frame_of(points);
  const pnf::detail::MortonFrame of_box = pnf::detail::morton_frame(box.min, box.max, {});
  EXPECT_EQ(own.low, of_box.low);
  EXPECT_EQ(own.to_cells, of_box.to_cells);
}

}  // namespace
