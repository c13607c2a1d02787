// The judge's vectorised arithmetic: exp over arrays (lib/src/auto/vector_exp.hpp) and the quadric
// fit's sums in lanes (lib/src/auto/quadric_moments.hpp), each the same bits at every vector width.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "auto/quadric_moments.hpp"
#include "auto/vector_exp.hpp"

namespace pnf::test {
namespace {

// The Gaussian weights' exponents -r^2/2 (0 down to past exp's underflow), a few positive values
// and a count that leaves a tail at every width.
std::vector<double> exponents() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> r(0, 40);
  std::vector<double> x;
  for (int k = 0; k < 1001; ++k) {
    const double residual = r(rng);
    x.push_back(-0.5 * residual * residual);
  }
  for (double v : {0.0, -1e-300, -708.0, -744.0, -746.0, 1.0, 3.5, 700.0}) x.push_back(v);
  return x;
}

TEST(VectorExp, EveryWidthGivesTheSameBitsWithinOneUlp) {
  const std::vector<double> x = exponents();
  std::vector<double> widest = x;
  detail::exp_in_place(widest.data(), widest.size());
  for (int lanes : {8, 4, 2, 1}) {
    std::vector<double> y = x;
    detail::exp_in_place_at_most(y.data(), y.size(), lanes);
    EXPECT_EQ(0, std::memcmp(y.data(), widest.data(), y.size() * sizeof(double))) << lanes << " lanes";
  }
  for (std::size_t k = 0; k < x.size(); ++k) {
    const long double exact = std::exp(static_cast<long double>(x[k]));
    const double ulp = std::nextafter(double(exact), HUGE_VAL) - double(exact);
    // Where exp underflows to a subnormal, an ulp of the result is 2^-1074: compare against that.
    EXPECT_LE(std::abs(static_cast<long double>(widest[k]) - exact), static_cast<long double>(ulp)) << x[k];
  }
}

// The sums a plain loop makes in the lanes' order (quadric_moments.hpp), and in long double.
struct Reference {
  double lanes[detail::kQuadricMoments];
  long double exact[detail::kQuadricMoments];
};
Reference reference(const std::vector<double>& w, const std::vector<double>& u, const std::vector<double>& v,
                    const std::vector<double>& h) {
  double partial[detail::kQuadricMoments][detail::kMomentLanes] = {};
  Reference out{};
  for (std::size_t k = 0; k < w.size(); ++k) {
    // 1 u v uu uv vv uuu uuv uvv vvv uuuu uuuv uuvv uvvv vvvv, then h times 1 u v uu uv vv.
    const int powers[15][2] = {{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1}, {0, 2}, {3, 0}, {2, 1},
                               {1, 2}, {0, 3}, {4, 0}, {3, 1}, {2, 2}, {1, 3}, {0, 4}};
    for (int q = 0; q < detail::kQuadricMoments; ++q) {
      const int* p = powers[q < 15 ? q : q - 15];
      const bool with_h = q >= 15;
      // The product in the order the library forms it: w, then u's, then v's, then h.
      double term = w[k];
      for (int a = 0; a < p[0]; ++a) term *= u[k];
      for (int b = 0; b < p[1]; ++b) term *= v[k];
      if (with_h) term *= h[k];
      partial[q][k % detail::kMomentLanes] += term;
      out.exact[q] += static_cast<long double>(w[k]) * std::pow(static_cast<long double>(u[k]), p[0]) *
                      std::pow(static_cast<long double>(v[k]), p[1]) * (with_h ? h[k] : 1.0L);
    }
  }
  for (int q = 0; q < detail::kQuadricMoments; ++q) {
    out.lanes[q] = 0;
    for (int j = 0; j < detail::kMomentLanes; ++j) out.lanes[q] += partial[q][j];
  }
  return out;
}

TEST(QuadricMoments, SumInTheLanesOrderOnThisCpuAndAreAccurate) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coordinate(-1, 1), weight(0, 1);
  for (std::size_t count : {std::size_t(0), std::size_t(5), std::size_t(257), std::size_t(4097)}) {
    std::vector<double> w(count), u(count), v(count), h(count);
    for (std::size_t k = 0; k < count; ++k) {
      w[k] = weight(rng), u[k] = coordinate(rng), v[k] = coordinate(rng), h[k] = 0.1 * coordinate(rng);
    }
    double sums[detail::kQuadricMoments];
    detail::quadric_moment_sums(w.data(), u.data(), v.data(), h.data(), count, sums);
    const Reference expected = reference(w, u, v, h);
    for (int q = 0; q < detail::kQuadricMoments; ++q) {
      // This CPU's copy (AVX-512 or AVX2 where it has them) against the plain loop, bit for bit.
      EXPECT_EQ(expected.lanes[q], sums[q]) << "moment " << q << ", " << count << " points";
      // And the sums themselves: each term is under 1 in size, so 1e-13 of the count bounds their rounding.
      EXPECT_NEAR(double(expected.exact[q]), sums[q], 1e-13 * double(count + 1)) << "moment " << q;
    }
  }
}

}  // namespace
}  // namespace pnf::test
