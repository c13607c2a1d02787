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

// Nominal floating-point operations per neighbour pair in pnf_eval_F (kernels/pnf_filter.h),
// counting the dual-number arithmetic as written: a dual multiply is 10 flops (1 + 3 x 3), a dual
// add or scale 4, exp 1 + 3. Per pair: |p-x|^2 38, h 20, exponent 22, exp 4, projection 24,
// sums 46, local offsets 6. The compiler folds some of them (the seed partials are constants),
// so this is an upper bound on the work done, the same for every device.
constexpr double kFlopsPerPair = 160;

// Names: "face" (75k points, sigma_f 4, sigma_g 0.5), "dog" (400k, sigma_f 8), "bunny" (the
// 362k raw Stanford scans, normals by pnf::estimate_normals; needs the team's data),
// "big" (2M points, sigma_f 8: 6.5 GB of lists, so it runs in chunks), "sweep-N" (N points,
// sigma_f 4). Synthetic ones are the scanned house of synthetic_shapes.hpp.
// Returns an empty name when the workload cannot be made (bunny without the data).
Workload make_workload(const std::string& name, const std::string& shared_data_dir);

}  // namespace pnf::bench
