// The shared per-point math (kernels/pnf_filter.h) in double: its dual-number Jacobian against
// central finite differences, F against an independent brute-force evaluation, and the normal
// update against analytic cases.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "spatial/spatial_index.hpp"
#include "pnf_filter.h"

namespace {

struct RandomCloud {
  std::vector<double> positions, normals;
};

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
  return c;
}

pnf_dvec3 constant_dvec(double x, double y, double z) {
  pnf_dvec3 r;
  r.x = pnf_dual_const(x);
  r.y = pnf_dual_const(y);
  r.z = pnf_dual_const(z);
  return r;
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
    for (int s = 0; s < 400; s += 7) {
      pnf_vec3 origin = pnf_load_vec3(cloud.positions.data(), s);
      pnf_dvec3 ad = pnf_eval_F(pnf_dvec3_seed(pnf_make_vec3(0, 0, 0)), origin, lists.indices.data(), lists.offsets[s],
                                lists.offsets[s + 1], cloud.positions.data(), cloud.normals.data(), c);
      double scale = 0;
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) scale = std::max(scale, std::fabs(partial(ad, i, k)));
      for (int k = 0; k < 3; ++k) {
        double e[3] = {0, 0, 0};
        e[k] = step;
        auto at = [&](double sign) {
          return pnf_eval_F(constant_dvec(sign * e[0], sign * e[1], sign * e[2]), origin, lists.indices.data(),
                            lists.offsets[s], lists.offsets[s + 1], cloud.positions.data(), cloud.normals.data(), c);
        };
        pnf_dvec3 plus = at(+1), minus = at(-1);
        for (int i = 0; i < 3; ++i) {
          double fd = (value(plus, i) - value(minus, i)) / (2 * step);
          EXPECT_NEAR(partial(ad, i, k), fd, 1e-6 * scale)
              << "seed " << seed << " point " << s << " dF" << i << "/dx" << k;
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
    // Independent: SPEC's formulas written out with two separate exponentials and a brute-force
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
    pnf_vec3 origin = pnf_load_vec3(P, s);
    pnf_dvec3 f = pnf_eval_F(constant_dvec(0.01, -0.02, 0.005), origin, lists.indices.data(), lists.offsets[s],
                             lists.offsets[s + 1], P, N, c);
    const double o[3] = {origin.x, origin.y, origin.z};
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(value(f, i) + o[i], sum_wp[i] / sum_w, 1e-12) << "point " << s;
  }
}

TEST(PnfFilter, PlaneJacobianIsTheTangentProjection) {
  // On the plane z = 0 with normals +z every projection is (x, y, 0): F(x) = (x, y, 0) and
  // J = diag(1, 1, 0) exactly, whatever the weights.
  std::vector<double> positions, normals;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 50; ++i) {
    positions.insert(positions.end(), {u(rng), u(rng), 0.0});
    normals.insert(normals.end(), {0.0, 0.0, 1.0});
  }
  std::vector<std::uint32_t> indices(50);
  for (int i = 0; i < 50; ++i) indices[i] = i;
  pnf_dvec3 f = pnf_eval_F(pnf_dvec3_seed(pnf_make_vec3(0, 0, 0)), pnf_load_vec3(positions.data(), 0), indices.data(),
                           0, 50, positions.data(), normals.data(), pnf_make_coeffs(0.5, 0.1));
  const double expected[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 0}};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(partial(f, i, k), expected[i][k], 1e-14);
}

// A pnf_dvec3 whose partials are the given Jacobian (rows i, columns k).
pnf_dvec3 with_jacobian(const double j[3][3]) {
  pnf_dvec3 f = constant_dvec(0, 0, 0);
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
  pnf_vec3 out = pnf_update_normal(with_jacobian(r), n);
  EXPECT_NEAR(out.x, std::cos(a), 1e-15);
  EXPECT_NEAR(out.y, std::sin(a), 1e-15);
  EXPECT_NEAR(out.z, 0, 1e-15);
}

TEST(PnfFilter, UpdateUsesTheInverseTransposeOfAShear) {
  // J = [[1, 0, 0], [0, 1, 0], [k, 0, 1]] maps the plane z = 0 onto z = k x, whose normal is
  // (-k, 0, 1)/sqrt(1 + k^2); the update must give exactly that from n = +z.
  const double k = 0.75;
  const double j[3][3] = {{1, 0, 0}, {0, 1, 0}, {k, 0, 1}};
  pnf_vec3 out = pnf_update_normal(with_jacobian(j), pnf_make_vec3(0, 0, 1));
  const double len = std::sqrt(1 + k * k);
  EXPECT_NEAR(out.x, -k / len, 1e-15);
  EXPECT_NEAR(out.y, 0, 1e-15);
  EXPECT_NEAR(out.z, 1 / len, 1e-15);
}

TEST(PnfFilter, UpdateNeverTurnsANormalToTheOtherSide) {
  // A reflection has det -1, so C n = -R n: the flip rule must bring it back to n's side.
  const double j[3][3] = {{-1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  pnf_vec3 n = pnf_make_vec3(0.6, 0, 0.8);
  pnf_vec3 out = pnf_update_normal(with_jacobian(j), n);
  EXPECT_GT(out.x * n.x + out.y * n.y + out.z * n.z, 0);
  EXPECT_NEAR(out.x, -0.6, 1e-15);  // the reflected direction, flipped: (-0.6, 0, 0.8) -> itself
  EXPECT_NEAR(out.z, 0.8, 1e-15);
}

TEST(PnfFilter, DegenerateJacobianKeepsTheNormal) {
  pnf_vec3 n = pnf_make_vec3(0, 0.6, 0.8);
  const double zero[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  const double rank_one[3][3] = {{1, 2, 3}, {2, 4, 6}, {0, 0, 0}};  // all 2x2 minors vanish: C = 0
  for (const auto* j : {zero, rank_one}) {
    pnf_vec3 out = pnf_update_normal(with_jacobian(j), n);
    EXPECT_EQ(out.x, n.x);
    EXPECT_EQ(out.y, n.y);
    EXPECT_EQ(out.z, n.z);
  }
}

}  // namespace
