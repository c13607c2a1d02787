// The workloads the harness measures: the paper's face and dog settings, a real scan when the
// team's data is present, and a size sweep.
#pragma once

#include <string>
#include <vector>

#include "pnf/filter_params.hpp"
#include "pnf/point_cloud.hpp"

namespace pnf::bench {

struct Workload {
  std::string name;
  std::string source;  // where the points came from
  PointCloud cloud;
  FilterParams params;
};

// Useful floating-point operations per neighbour pair, the figure every GFLOP/s of the bench and
// of docs/performance.md is computed with (pairs per second x this). Fixed by the method, not by
// the code, so that figures stay comparable when the code changes (as CLBlast counts 2n for an
// axpy however it is written): the per-pair arithmetic of the span{d, n} dual-number formulation
// of kernels/pnf_filter.h, a multiply, add or subtract 1 flop (an FMA 2), exp 1, the weight cut's
// max and select 0, the per-point work (final division, cofactor update) left out (it is under
// 1% at 200 neighbours). Per pair: d = p - x 3, |d|^2 5, h = d.n 5, exponent and its gradient
// (g h, f |d|^2 + g h h, 2 g h) 5, exp 1, w's gradient 2, q = w h with its gradient 4, sum w 1,
// sum grad w 12, sum q n 6, grad q expanded 9, sum n (grad q)^T 18: 71.
constexpr double kFlopsPerPair = 71;

// Names: "face" (75k points, sigma_f 4, sigma_g 0.5), "dog" (400k, sigma_f 8), "bunny" (the
// 362k raw Stanford scans, normals by pnf::estimate_normals; needs the team's data),
// "cube" (a noisy 400k-point cube, sigma_f 8: sharp edges everywhere), "big" (2M points,
// sigma_f 8: 6.5 GB of lists, so it runs in chunks), "stray" (the face and one point 1e9 away:
// docs/method.md, "Curve order"), "sweep-N" (N points, sigma_f 4). Synthetic ones are the scanned house of synthetic_shapes.hpp.
// Returns an empty name when the workload cannot be made (bunny without the data).
Workload make_workload(const std::string& name, const std::string& shared_data_dir);

}  // namespace pnf::bench
