// Internal to --auto: the normal equations of a weighted quadric height fit (the estimate's fits,
// sample_fit.cpp, and the surface judge's, surface_judge.cpp), their sums vectorised with the same
// bits on every CPU.
#pragma once

#include <Eigen/Core>
#include <cstddef>

namespace pnf::detail {

// The 15 weighted moments of u^a v^b (a + b <= 4) in the order 1 u v uu uv vv uuu uuv uvv vvv
// uuuu uuuv uuvv uvvv vvvv, then the 6 of h u^a v^b in the order 1 u v uu uv vv: the normal
// equations of the quadric h = c0 + c1 u + c2 v + c3 u^2 + c4 uv + c5 v^2.
constexpr int kQuadricMoments = 21;
// They are summed in this many interleaved partial sums (point k into lane k mod kMomentLanes,
// each lane in point order), then the lanes in order: the order is the code's, not the CPU's, so
// the copies built for wider vectors (PNF_WIDE_CLONES, vectorised across the lanes) give the
// same bits as the plain one, and the fits the same on every CPU. The 8 judged scores of a noisy
// cloud's run (fits of 4097 points) took 0.089 s instead of 0.151 s with the sums one point
// after another (docs/auto.md, "Time").
constexpr int kMomentLanes = 8;

// Over points [0, count) of the arrays of weights w, tangent coordinates u, v and heights h.
void quadric_moment_sums(const double* w, const double* u, const double* v, const double* h, std::size_t count,
                         double (&out)[kQuadricMoments]);

// A^T W A of the fit (rows and columns 1 u v uu uv vv) and A^T W h, from the sums.
using QuadricMatrix = Eigen::Matrix<double, 6, 6>;
using QuadricVector = Eigen::Matrix<double, 6, 1>;
QuadricMatrix quadric_normal_matrix(const double (&sums)[kQuadricMoments]);
QuadricVector quadric_right_side(const double (&sums)[kQuadricMoments]);

// The fitted quadric's height at (u, v): c0 + c1 u + c2 v + c3 u^2 + c4 uv + c5 v^2.
inline double quadric_height(const QuadricVector& c, double u, double v) {
  return c(0) + u * (c(1) + c(3) * u + c(4) * v) + v * (c(2) + c(5) * v);
}

}  // namespace pnf::detail
