// The engine's hook for distributed runs (filter_engine.hpp, DistributedPart) without MPI: a
// cloud split in two parts, each with its halo found by brute force, filtered in two threads
// that swap halo normals through shared memory after every pass, equals the one-part run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <random>
#include <thread>

#include "filter_engine.hpp"
#include "pnf/mean_radius.hpp"
#include "reference_backend.hpp"
#include "test_clouds.hpp"

namespace {

using namespace pnf;
using pnf::test::angle_deg;

// Two parts re-centred on different origins and summed in a different neighbour order differ
// from one part by rounding only.
constexpr double kRoundingDeg = 1e-9;

// Two threads meet here (C++17 has no std::barrier).
class Barrier {
 public:
  void arrive_and_wait() {
    std::unique_lock<std::mutex> lock(mutex_);
    const int generation = generation_;
    if (++waiting_ == 2) {
      waiting_ = 0;
      ++generation_;
      wake_.notify_all();
    } else {
      wake_.wait(lock, [&] { return generation_ != generation; });
    }
  }

 private:
  std::mutex mutex_;
  std::condition_variable wake_;
  int waiting_ = 0, generation_ = 0;
};

struct Part {
  std::vector<std::size_t> ids;  // global ids: own points, then the halo
  std::size_t owned = 0;
};

TEST(FilterEngineParts, TwoPartsInTwoThreadsEqualOnePart) {
  PointCloud cloud = pnf::test::jittered_sphere(3000, 5.0, 3, 20);
  FilterParams params;
  params.iterations = 3;
  params.stop_change_deg = 1e-6;  // the stop rule's sums go through sum_over_processes
  params.mean_radius = estimate_mean_radius(cloud.positions);
  FilterOptions options;
  options.device = Device::reference();
  std::vector<Vec3> whole(cloud.size());
  auto backend = detail::make_reference_backend(1);
  const FilterSummary one = detail::run_filter(*backend, options, cloud, whole, params, {});

  // Split at x = 0.3; the halo of each part: the other part's points within 2 sigma_f (+ a hair).
  const double reach = 2 * params.sigma_f * params.mean_radius * (1 + 1e-9);
  Part parts[2];
  for (std::size_t i = 0; i < cloud.size(); ++i) parts[cloud.positions[i][0] < 0.3 ? 0 : 1].ids.push_back(i);
  for (Part& p : parts) p.owned = p.ids.size();
  for (int a = 0; a < 2; ++a) {
    const Part& other = parts[1 - a];
    for (std::size_t k = 0; k < other.owned; ++k) {
      const Vec3& p = cloud.positions[other.ids[k]];
      for (std::size_t m = 0; m < parts[a].owned; ++m) {
        const Vec3& q = cloud.positions[parts[a].ids[m]];
        if (std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]) <= reach) {
          parts[a].ids.push_back(other.ids[k]);
          break;
        }
      }
    }
  }
  ASSERT_GT(parts[0].ids.size(), parts[0].owned);
  ASSERT_GT(parts[1].ids.size(), parts[1].owned);

  std::vector<Vec3> shared(cloud.size()), result(cloud.size());
  double sums[2][2] = {};
  Barrier sync;
  FilterSummary summaries[2];
  auto work = [&](int a) {
    const Part& p = parts[a];
    PointCloud mine;
    for (std::size_t i : p.ids) {
      mine.positions.push_back(cloud.positions[i]);
      mine.normals.push_back(cloud.normals[i]);
    }
    detail::DistributedPart part;
    part.owned = p.owned;
    part.exchange_halo = [&](const std::vector<double>& owned, std::vector<double>& halo) {
      for (std::size_t k = 0; k < p.owned; ++k) shared[p.ids[k]] = {owned[3 * k], owned[3 * k + 1], owned[3 * k + 2]};
      sync.arrive_and_wait();
      for (std::size_t k = p.owned; k < p.ids.size(); ++k) {
        for (int c = 0; c < 3; ++c) halo[3 * (k - p.owned) + std::size_t(c)] = shared[p.ids[k]][std::size_t(c)];
      }
      sync.arrive_and_wait();
    };
    part.sum_over_processes = [&](double* values, int count) {
      for (int c = 0; c < count; ++c) sums[a][c] = values[c];
      sync.arrive_and_wait();
      for (int c = 0; c < count; ++c) values[c] = sums[0][c] + sums[1][c];
      sync.arrive_and_wait();
    };
    std::vector<Vec3> out(p.owned);
    auto engine = detail::make_reference_backend(1);
    summaries[a] = detail::run_filter(*engine, options, mine, out, params, {}, &part);
    for (std::size_t k = 0; k < p.owned; ++k) result[p.ids[k]] = out[k];
  };
  std::thread first(work, 0), second(work, 1);
  first.join();
  second.join();

  double worst = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) worst = std::max(worst, angle_deg(result[i], whole[i]));
  EXPECT_LE(worst, kRoundingDeg);
  EXPECT_EQ(summaries[0].passes_run, one.passes_run);
  EXPECT_EQ(summaries[1].passes_run, one.passes_run);
  EXPECT_EQ(summaries[0].neighbour_pairs + summaries[1].neighbour_pairs, one.neighbour_pairs);
}

}  // namespace

namespace {

// The stop rule's change adds whole quanta, so parts summed in any grouping give the whole's
// total bit for bit (a sum of doubles would round differently), and it is the plain sum of the
// angles to within half a quantum a point.
TEST(StopRuleChange, PartsAddUpToTheWholeExactlyInAnyGrouping) {
  std::mt19937 rng(9);
  std::normal_distribution<double> g(0, 1);
  const std::size_t n = 10007;
  std::vector<double> a(3 * n), b(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    double u[3] = {g(rng), g(rng), g(rng)}, v[3];
    for (int c = 0; c < 3; ++c) v[c] = u[c] + 0.05 * g(rng);
    const double lu = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    const double lv = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int c = 0; c < 3; ++c) a[3 * i + c] = u[c] / lu, b[3 * i + c] = v[c] / lv;
  }
  const double whole = detail::change_quanta(a, b, n);
  double plain = 0;
  for (std::size_t i = 0; i < n; ++i)
    plain += angle_deg({a[3 * i], a[3 * i + 1], a[3 * i + 2]}, {b[3 * i], b[3 * i + 1], b[3 * i + 2]});
  EXPECT_NEAR(whole / detail::kChangeQuantaPerDegree, plain, 0.5 * double(n) / detail::kChangeQuantaPerDegree);
  for (const std::size_t parts : {2, 3, 7}) {
    double total = 0;
    for (std::size_t p = parts; p-- > 0;) {  // last part first: another order than the whole's
      const std::size_t first = p * n / parts, last = (p + 1) * n / parts;
      const std::vector<double> pa(a.begin() + 3 * first, a.begin() + 3 * last);
      const std::vector<double> pb(b.begin() + 3 * first, b.begin() + 3 * last);
      total += detail::change_quanta(pa, pb, last - first);
    }
    EXPECT_EQ(total, whole) << parts << " parts";
  }
}

}  // namespace

namespace {

// A part with no points still takes part in every pass's exchange, the twin's passes first, so
// that the processes with points are not left waiting (a distributed twin run: --auto's Stein
// route across ranks).
TEST(FilterEngineParts, AnIdlePartTakesPartInTheTwinsPassesThenItsOwn) {
  FilterParams params;
  params.iterations = 3;
  params.mean_radius = 0.1;  // a part must be given it
  std::vector<char> calls;   // 't' for the twin's exchange, 'r' for the run's
  detail::DistributedPart part, twin_part;
  part.exchange_halo = [&](const std::vector<double>&, std::vector<double>&) { calls.push_back('r'); };
  twin_part.exchange_halo = [&](const std::vector<double>&, std::vector<double>&) { calls.push_back('t'); };
  const detail::TwinRun twin{Vec3ArrayView(), &twin_part};
  auto backend = detail::make_reference_backend(1);
  FilterOptions options{Device::reference()};
  std::vector<Vec3> none;
  detail::run_filter(*backend, options, CloudView(Vec3ArrayView(), Vec3ArrayView()), MutableVec3ArrayView(none), params,
                     {}, &part, &twin);
  EXPECT_EQ(std::string(calls.begin(), calls.end()), "tttrrr");
}

}  // namespace
