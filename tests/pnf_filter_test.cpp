// The shared per-point math (kernels/pnf_filter.h) in double: its dual-number Jacobian against
// central finite differences, F against an independent brute-force evaluation, and the normal
// update against analytic cases.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <cstdlib>
#include <memory>
#include <string>

#include "cl_runtime.hpp"
#include "kernel_source.hpp"
#include "pnf/error.hpp"
#include "pnf_filter.h"
#include "spatial/spatial_index.hpp"
#include "test_backends.hpp"

namespace {

struct RandomCloud {
  std::vector<double> positions, normals;       // N by 3, for the neighbour search and brute force
  std::vector<pnf_real4> positions4, normals4;  // the layout pnf_filter.h reads
};

std::vector<pnf_real4> to_real4(const std::vector<double>& v) {
  std::vector<pnf_real4> out;
  for (std::size_t i = 0; i + 2 < v.size(); i += 3) out.push_back(pnf_real4{v[i], v[i + 1], v[i + 2], 0});
  return out;
}

// Points in a unit cube with random unit normals: no structure the math could lean on.
RandomCloud random_cloud(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g(0, 1);
  RandomCloud c;
  for (int i = 0; i < n; ++i) {
    double nx = g(rng), ny = g(rng), nz = g(rng), len = std::sqrt(nx * nx + ny * ny + nz * nz);
    c.positions.insert(c.positions.end(), {u(rng), u(rng), u(rng)});
    c.normals.insert(c.normals.end(), {nx / len, ny / len, nz / len});
  }
  c.positions4 = to_real4(c.positions);
  c.normals4 = to_real4(c.normals);
  return c;
}

double value(const pnf_dvec3& f, int i) { return i == 0 ? f.x.v : i == 1 ? f.y.v : f.z.v; }
double partial(const pnf_dvec3& f, int i, int k) { return i == 0 ? f.x.d[k] : i == 1 ? f.y.d[k] : f.z.d[k]; }

TEST(PnfFilter, JacobianMatchesCentralFiniteDifferences) {
  for (unsigned seed : {1u, 2u, 3u}) {
    RandomCloud cloud = random_cloud(400, seed);
    const double sigma_f = 0.15, sigma_g = 0.1;
    const pnf::detail::SpatialIndex search(cloud.positions);
    std::vector<std::uint32_t> counts = search.count_within(PNF_SUPPORT_IN_SIGMA_F * sigma_f);
    pnf::detail::CsrLists lists = search.lists_within(PNF_SUPPORT_IN_SIGMA_F * sigma_f, 0, 400, counts);
    pnf_coeffs c = pnf_make_coeffs(sigma_f, sigma_g);
    // Central differences have error O(step^2 |F'''|) + O(eps |F| / step); this step balances
    // them far below the 1e-6 asked for at this scale (sigma ~ 0.1).
    const double step = 1e-6;
    // At the sample itself (the filter's query) and off it, so that the Jacobian's terms in
    // x - o are exercised too.
    for (const pnf_vec3 at : {pnf_make_vec3(0, 0, 0), pnf_make_vec3(0.012, -0.007, 0.02)}) {
      for (int s = 0; s < 400; s += 7) {
        auto eval = [&](pnf_vec3 x) {
          return pnf_eval_F(x, pnf_index(s), lists.indices.data(), lists.offsets[s], lists.offsets[s + 1],
                            cloud.positions4.data(), cloud.normals4.data(), c);
        };
        pnf_dvec3 ad = eval(at);
        double scale = 0;
        for (int i = 0; i < 3; ++i)
          for (int k = 0; k < 3; ++k) scale = std::max(scale, std::fabs(partial(ad, i, k)));
        for (int k = 0; k < 3; ++k) {
          double e[3] = {0, 0, 0};
          e[k] = step;
          pnf_dvec3 plus = eval(pnf_make_vec3(at.x + e[0], at.y + e[1], at.z + e[2]));
          pnf_dvec3 minus = eval(pnf_make_vec3(at.x - e[0], at.y - e[1], at.z - e[2]));
          for (int i = 0; i < 3; ++i) {
            double fd = (value(plus, i) - value(minus, i)) / (2 * step);
            EXPECT_NEAR(partial(ad, i, k), fd, 1e-6 * scale)
                << "seed " << seed << " point " << s << " dF" << i << "/dx" << k << " at x - o = (" << at.x << ", "
                << at.y << ", " << at.z << ")";
          }
        }
      }
    }
  }
}

TEST(PnfFilter, FMatchesBruteForceEvaluation) {
  RandomCloud cloud = random_cloud(300, 7);
  const double sigma_f = 0.2, sigma_g = 0.05;
  const pnf::detail::SpatialIndex search(cloud.positions);
  std::vector<std::uint32_t> counts = search.count_within(2 * sigma_f);
  pnf::detail::CsrLists lists = search.lists_within(2 * sigma_f, 0, 300, counts);
  pnf_coeffs c = pnf_make_coeffs(sigma_f, sigma_g);
  const double* P = cloud.positions.data();
  const double* N = cloud.normals.data();
  for (int s = 0; s < 300; s += 11) {
    // Independent: the formulas of docs/method.md written out with two separate exponentials and a brute-force
    // neighbour set, at a query point x off the sample itself.
    const double x[3] = {P[3 * s] + 0.01, P[3 * s + 1] - 0.02, P[3 * s + 2] + 0.005};
    double sum_w = 0, sum_wp[3] = {0, 0, 0};
    for (int p = 0; p < 300; ++p) {
      double ds = std::sqrt(std::pow(P[3 * p] - P[3 * s], 2) + std::pow(P[3 * p + 1] - P[3 * s + 1], 2) +
                            std::pow(P[3 * p + 2] - P[3 * s + 2], 2));
      if (ds > 2 * sigma_f) continue;
      double d[3] = {P[3 * p] - x[0], P[3 * p + 1] - x[1], P[3 * p + 2] - x[2]};
      double h = d[0] * N[3 * p] + d[1] * N[3 * p + 1] + d[2] * N[3 * p + 2];
      double dist = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      double w = std::exp(-dist * dist / (2 * sigma_f * sigma_f)) * std::exp(-h * h / (2 * sigma_g * sigma_g));
      sum_w += w;
      for (int i = 0; i < 3; ++i) sum_wp[i] += w * (x[i] + h * N[3 * p + i]);
    }
    pnf_dvec3 f = pnf_eval_F(pnf_make_vec3(0.01, -0.02, 0.005), pnf_index(s), lists.indices.data(), lists.offsets[s],
                             lists.offsets[s + 1], cloud.positions4.data(), cloud.normals4.data(), c);
    const double o[3] = {P[3 * s], P[3 * s + 1], P[3 * s + 2]};
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(value(f, i) + o[i], sum_wp[i] / sum_w, 1e-12) << "point " << s;
  }
}

TEST(PnfFilter, PlaneJacobianIsTheTangentProjection) {
  // On the plane z = 0 with normals +z every projection is (x, y, 0): F(x) = (x, y, 0) and
  // J = diag(1, 1, 0) exactly, whatever the weights.
  std::vector<pnf_real4> positions, normals;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 50; ++i) {
    positions.push_back(pnf_real4{u(rng), u(rng), 0.0, 0.0});
    normals.push_back(pnf_real4{0.0, 0.0, 1.0, 0.0});
  }
  std::vector<std::uint32_t> indices(50);
  for (int i = 0; i < 50; ++i) indices[i] = i;
  pnf_dvec3 f = pnf_eval_F(pnf_make_vec3(0, 0, 0), 0, indices.data(), 0, 50, positions.data(), normals.data(),
                           pnf_make_coeffs(0.5, 0.1));
  const double expected[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 0}};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(partial(f, i, k), expected[i][k], 1e-14);
}

// A pnf_dvec3 whose partials are the given Jacobian (rows i, columns k).
pnf_dvec3 with_jacobian(const double j[3][3]) {
  pnf_dvec3 f;
  f.x = pnf_dual_const(0);
  f.y = pnf_dual_const(0);
  f.z = pnf_dual_const(0);
  for (int k = 0; k < 3; ++k) {
    f.x.d[k] = j[0][k];
    f.y.d[k] = j[1][k];
    f.z.d[k] = j[2][k];
  }
  return f;
}

TEST(PnfFilter, UpdateOfARotationRotatesTheNormal) {
  // For a rotation R, adj(R)^T = det(R) R^-T = R: the normal turns with the surface.
  const double a = 0.3;
  const double r[3][3] = {{std::cos(a), -std::sin(a), 0}, {std::sin(a), std::cos(a), 0}, {0, 0, 1}};
  pnf_vec3 n = pnf_make_vec3(1, 0, 0);
  int kept = 1;
  pnf_vec3 out = pnf_update_normal(with_jacobian(r), n, &kept);
  EXPECT_EQ(kept, 0);
  EXPECT_NEAR(out.x, std::cos(a), 1e-15);
  EXPECT_NEAR(out.y, std::sin(a), 1e-15);
  EXPECT_NEAR(out.z, 0, 1e-15);
}

TEST(PnfFilter, UpdateUsesTheInverseTransposeOfAShear) {
  // J = [[1, 0, 0], [0, 1, 0], [k, 0, 1]] maps the plane z = 0 onto z = k x, whose normal is
  // (-k, 0, 1)/sqrt(1 + k^2); the update must give exactly that from n = +z.
  const double k = 0.75;
  const double j[3][3] = {{1, 0, 0}, {0, 1, 0}, {k, 0, 1}};
  int kept = 1;
  pnf_vec3 out = pnf_update_normal(with_jacobian(j), pnf_make_vec3(0, 0, 1), &kept);
  EXPECT_EQ(kept, 0);
  const double len = std::sqrt(1 + k * k);
  EXPECT_NEAR(out.x, -k / len, 1e-15);
  EXPECT_NEAR(out.y, 0, 1e-15);
  EXPECT_NEAR(out.z, 1 / len, 1e-15);
}

TEST(PnfFilter, UpdateNeverTurnsANormalToTheOtherSide) {
  // A reflection has det -1, so C n = -R n: the flip rule must bring it back to n's side.
  const double j[3][3] = {{-1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  pnf_vec3 n = pnf_make_vec3(0.6, 0, 0.8);
  int kept = 1;
  pnf_vec3 out = pnf_update_normal(with_jacobian(j), n, &kept);
  EXPECT_EQ(kept, 0);
  EXPECT_GT(out.x * n.x + out.y * n.y + out.z * n.z, 0);
  EXPECT_NEAR(out.x, -0.6, 1e-15);  // the reflected direction, flipped: (-0.6, 0, 0.8) -> itself
  EXPECT_NEAR(out.z, 0.8, 1e-15);
}

TEST(PnfFilter, DegenerateJacobianKeepsTheNormal) {
  pnf_vec3 n = pnf_make_vec3(0, 0.6, 0.8);
  const double zero[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  const double rank_one[3][3] = {{1, 2, 3}, {2, 4, 6}, {0, 0, 0}};  // all 2x2 minors vanish: C = 0
  for (const auto* j : {zero, rank_one}) {
    int kept = 0;
    pnf_vec3 out = pnf_update_normal(with_jacobian(j), n, &kept);
    EXPECT_EQ(kept, 1);
    EXPECT_EQ(out.x, n.x);
    EXPECT_EQ(out.y, n.y);
    EXPECT_EQ(out.z, n.z);
  }
}

// u v^T with entries that are not exact in binary: the computed minors are rounding, not 0, and
// |C| is of the same size as |C n|, so a threshold relative to |C| would normalise that noise.
void rank_one_jacobian(double j[3][3]) {
  const double u[3] = {0.3, -0.7, 1.1}, v[3] = {1.0 / 3, 0.1, -2.0 / 7};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) j[i][k] = u[i] * v[k];
}

TEST(PnfFilter, RoundedRankOneJacobianKeepsTheNormalInDouble) {
  double j[3][3];
  rank_one_jacobian(j);
  pnf_vec3 n = pnf_make_vec3(0, 0.6, 0.8);
  int kept = 0;
  pnf_vec3 out = pnf_update_normal(with_jacobian(j), n, &kept);
  EXPECT_EQ(kept, 1);
  EXPECT_EQ(out.x, n.x);
  EXPECT_EQ(out.y, n.y);
  EXPECT_EQ(out.z, n.z);
}

TEST(PnfFilter, RegularJacobianIsNotDegenerate) {
  const double shear[3][3] = {{1, 0, 0}, {0, 1, 0}, {0.75, 0, 1}};
  int kept = 1;
  pnf_update_normal(with_jacobian(shear), pnf_make_vec3(0, 0, 1), &kept);
  EXPECT_EQ(kept, 0);
}

// The same update in float, as the kernels run it: pnf_filter.h through a tiny OpenCL kernel.
// Cases: a rounded rank-1 J (kept), the zero J (kept), a shear (updated, as in double).
TEST(PnfFilter, RoundedRankOneJacobianKeepsTheNormalInFloat) {
  std::unique_ptr<pnf::detail::ClRuntime> runtime;
  try {
    runtime = std::make_unique<pnf::detail::ClRuntime>("");
  } catch (const pnf::Error& e) {
    PNF_OPENCL_OR_SKIP(e.what());
  }
  const std::string source = pnf::detail::kernel_source("filter.cl") + R"CL(
__kernel void pnf_test_update_normal(__global const float* jacobians, __global const float* normals,
                                     __global float* out, __global int* kept) {
  uint i = get_global_id(0);
  pnf_dvec3 f;
  f.x = pnf_dual_const(0);
  f.y = pnf_dual_const(0);
  f.z = pnf_dual_const(0);
  for (int k = 0; k < 3; ++k) {
    f.x.d[k] = jacobians[9 * i + k];
    f.y.d[k] = jacobians[9 * i + 3 + k];
    f.z.d[k] = jacobians[9 * i + 6 + k];
  }
  int k;
  pnf_vec3 n = pnf_update_normal(f, pnf_make_vec3(normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]), &k);
  out[3 * i] = n.x;
  out[3 * i + 1] = n.y;
  out[3 * i + 2] = n.z;
  kept[i] = k;
}
)CL";
  double rank_one[3][3];
  rank_one_jacobian(rank_one);
  const double zero[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  const double shear[3][3] = {{1, 0, 0}, {0, 1, 0}, {0.75, 0, 1}};
  std::vector<float> jacobians, normals;
  for (const double(*j)[3] : {static_cast<const double(*)[3]>(rank_one), zero, shear}) {
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) jacobians.push_back(float(j[i][k]));
  }
  normals = {0, 0.6f, 0.8f, 0, 0.6f, 0.8f, 0, 0, 1};
  std::vector<float> out(9);
  std::vector<int> kept(3, -1);
  try {
    cl::Context& context = runtime->context();
    cl::Program program(context, source);
    try {
      program.build("-cl-std=CL1.2 -DPNF_LANES=1");
    } catch (const cl::Error&) {
      FAIL() << program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(runtime->device());
    }
    cl::Buffer j_buf(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, jacobians.size() * sizeof(float),
                     jacobians.data());
    cl::Buffer n_buf(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, normals.size() * sizeof(float), normals.data());
    cl::Buffer out_buf(context, CL_MEM_WRITE_ONLY, out.size() * sizeof(float));
    cl::Buffer kept_buf(context, CL_MEM_WRITE_ONLY, kept.size() * sizeof(int));
    cl::Kernel kernel(program, "pnf_test_update_normal");
    kernel.setArg(0, j_buf);
    kernel.setArg(1, n_buf);
    kernel.setArg(2, out_buf);
    kernel.setArg(3, kept_buf);
    runtime->queue().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(3));
    runtime->queue().enqueueReadBuffer(out_buf, CL_TRUE, 0, out.size() * sizeof(float), out.data());
    runtime->queue().enqueueReadBuffer(kept_buf, CL_TRUE, 0, kept.size() * sizeof(int), kept.data());
  } catch (const cl::Error& e) {
    FAIL() << e.what() << " " << pnf::detail::cl_error_name(e.err());
  }
  for (int c = 0; c < 2; ++c) {
    EXPECT_EQ(kept[c], 1) << "case " << c;
    EXPECT_EQ(out[3 * c], 0.0f) << "case " << c;
    EXPECT_EQ(out[3 * c + 1], 0.6f) << "case " << c;
    EXPECT_EQ(out[3 * c + 2], 0.8f) << "case " << c;
  }
  EXPECT_EQ(kept[2], 0);
  const double len = std::sqrt(1 + 0.75 * 0.75);
  EXPECT_NEAR(out[6], -0.75 / len, 1e-6);  // float rounding of the cofactors
  EXPECT_NEAR(out[7], 0, 1e-6);
  EXPECT_NEAR(out[8], 1 / len, 1e-6);
}

}  // namespace
