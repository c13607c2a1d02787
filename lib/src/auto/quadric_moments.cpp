// The quadric fit's sums in lanes (quadric_moments.hpp).
#include "quadric_moments.hpp"

#include "wide_clones.hpp"

namespace pnf::detail {
namespace {

// Adds points [k, k + lanes) into the lanes [0, lanes).
inline void add_moments(double (&s)[kQuadricMoments][kMomentLanes], const double* w, const double* u, const double* v,
                        const double* h, std::size_t k, int lanes) {
  for (int j = 0; j < lanes; ++j) {
    const double wj = w[k + j], uj = u[k + j], vj = v[k + j], hj = h[k + j];
    const double wu = wj * uj, wv = wj * vj, wuu = wu * uj, wuv = wu * vj, wvv = wv * vj;
    const double wuuu = wuu * uj, wuuv = wuu * vj, wuvv = wuv * vj, wvvv = wvv * vj;
    s[0][j] += wj, s[1][j] += wu, s[2][j] += wv, s[3][j] += wuu, s[4][j] += wuv, s[5][j] += wvv;
    s[6][j] += wuuu, s[7][j] += wuuv, s[8][j] += wuvv, s[9][j] += wvvv;
    s[10][j] += wuuu * uj, s[11][j] += wuuu * vj, s[12][j] += wuuv * vj, s[13][j] += wuvv * vj, s[14][j] += wvvv * vj;
    s[15][j] += wj * hj, s[16][j] += wu * hj, s[17][j] += wv * hj;
    s[18][j] += wuu * hj, s[19][j] += wuv * hj, s[20][j] += wvv * hj;
  }
}
}  // namespace

PNF_WIDE_CLONES void quadric_moment_sums(const double* w, const double* u, const double* v, const double* h,
                                         std::size_t count, double (&out)[kQuadricMoments]) {
  double s[kQuadricMoments][kMomentLanes] = {};
  std::size_t k = 0;
  for (; k + kMomentLanes <= count; k += kMomentLanes) add_moments(s, w, u, v, h, k, kMomentLanes);
  add_moments(s, w, u, v, h, k, int(count - k));
  for (int q = 0; q < kQuadricMoments; ++q) {
    out[q] = 0;
    for (int j = 0; j < kMomentLanes; ++j) out[q] += s[q][j];
  }
}

QuadricMatrix quadric_normal_matrix(const double (&sums)[kQuadricMoments]) {
  // Entry (i, j) is the moment of the product of rows i and j.
  constexpr int kMoment[6][6] = {{0, 1, 2, 3, 4, 5},    {1, 3, 4, 6, 7, 8},    {2, 4, 5, 7, 8, 9},
                                 {3, 6, 7, 10, 11, 12}, {4, 7, 8, 11, 12, 13}, {5, 8, 9, 12, 13, 14}};
  QuadricMatrix m;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) m(i, j) = sums[kMoment[i][j]];
  }
  return m;
}

QuadricVector quadric_right_side(const double (&sums)[kQuadricMoments]) {
  return Eigen::Map<const QuadricVector>(sums + 15);
}

}  // namespace pnf::detail
