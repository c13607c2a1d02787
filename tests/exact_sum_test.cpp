// pnf::detail::ExactSum (lib/src/exact_sum.hpp): exact, so the same bits in any order and any
// grouping; checked against sums whose exact value is known.
#include "exact_sum.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace {

using pnf::detail::ExactSum;

double exact_sum_of(const std::vector<double>& values) {
  ExactSum sum;
  for (double v : values) sum.add(v);
  return sum.value();
}

TEST(ExactSum, KeepsWhatAPlainSumLoses) {
  EXPECT_EQ(exact_sum_of({1e16, 1.0, -1e16}), 1.0);  // a plain sum gives 0
  EXPECT_EQ(exact_sum_of({1e300, 1e-300, -1e300}), 1e-300);
  // Ten times the double nearest 0.1 is 1 + 5.55e-17, nearest 1.0; a plain sum gives 1 - 1.1e-16.
  EXPECT_EQ(exact_sum_of(std::vector<double>(10, 0.1)), 1.0);
  const double tiny = std::numeric_limits<double>::denorm_min();
  EXPECT_EQ(exact_sum_of({tiny, tiny, 3 * tiny}), 5 * tiny);
  EXPECT_EQ(exact_sum_of({-2.5, 0.5}), -2.0);
  EXPECT_EQ(exact_sum_of({}), 0.0);
  EXPECT_EQ(exact_sum_of({1.0, std::nan(""), std::numeric_limits<double>::infinity()}), 1.0);
}

TEST(ExactSum, SameBitsInAnyOrderAndGrouping) {
  std::mt19937 rng(3);
  std::lognormal_distribution<double> magnitude(0, 6);
  std::vector<double> values;
  for (int i = 0; i < 20000; ++i) values.push_back((i % 3 == 0 ? -1 : 1) * magnitude(rng));
  const double whole = exact_sum_of(values);
  // Within an ulp or so of a long-double sum of the values sorted by magnitude.
  std::vector<double> sorted = values;
  std::sort(sorted.begin(), sorted.end(), [](double a, double b) { return std::fabs(a) < std::fabs(b); });
  long double careful = 0;
  for (double v : sorted) careful += v;
  EXPECT_NEAR(whole, double(careful), 4 * std::fabs(whole) * std::numeric_limits<double>::epsilon());
  for (unsigned seed : {1u, 2u}) {
    std::shuffle(values.begin(), values.end(), std::mt19937(seed));
    EXPECT_EQ(exact_sum_of(values), whole);
    // In three parts added up, as ranks add theirs.
    ExactSum parts[3];
    for (std::size_t i = 0; i < values.size(); ++i) parts[i * 3 / values.size()].add(values[i]);
    ExactSum total;
    for (const ExactSum& part : parts) total.add(part);
    EXPECT_EQ(total.value(), whole);
    // Digits added as integers, as MPI_Allreduce adds them.
    ExactSum reduced = parts[0];
    auto& digits = reduced.carried_digits();
    for (int p = 1; p < 3; ++p) {
      const auto& more = parts[p].carried_digits();
      for (std::size_t d = 0; d < digits.size(); ++d) digits[d] += more[d];
    }
    EXPECT_EQ(reduced.value(), whole);
  }
}

}  // namespace
