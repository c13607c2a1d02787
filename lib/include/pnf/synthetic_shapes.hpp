// pnf::make_scanned_house — a synthetic, scanned-looking model with sharp edges and known
// normals, for demos, tests and benchmarks that must not depend on outside data.
#pragma once

#include <cstddef>
#include <vector>

#include "pnf/point_cloud.hpp"

namespace pnf {

// How the synthetic "scan" is corrupted.
struct ScanNoise {
  double position = 0.1;       // std. dev. of the offset along the true normal, in sample spacings
  double normal_degrees = 15;  // std. dev. of the normal's tilt on each tangent axis, in degrees
  unsigned seed = 1;           // same seed, same cloud, on every machine
};

struct SyntheticCloud {
  PointCloud cloud;                // noisy positions and noisy unit normals
  std::vector<Vec3> true_normals;  // N, the exact outward normal of each sample's face
  double spacing = 0;              // sample spacing, model units
};

// A closed house shape, 100 units wide: a 100 x 100 x 60 box under a 45-degree gable roof
// (ridge at height 110), so it has 90-degree edges, a 90-degree ridge and 135-degree eaves.
// Each of its 7 planar faces is sampled on a jittered grid; about `points` samples in all
// (>= 100). Positions are offset from the origin by (1000, 2000, 500), as scans usually are.
SyntheticCloud make_scanned_house(std::size_t points, const ScanNoise& noise = {});

}  // namespace pnf
