#include "bench_workloads.hpp"

#include <cmath>
#include <fstream>
#include <random>

#include "geometry.hpp"
#include "pnf/estimate_normals.hpp"
#include "pnf/point_file.hpp"
#include "pnf/synthetic_shapes.hpp"

namespace pnf::bench {
namespace {

Workload synthetic(const std::string& name, std::size_t points, double sigma_f, double sigma_g) {
  Workload w;
  w.name = name;
  w.source = "synthetic scanned house";
  w.cloud = make_scanned_house(points).cloud;
  w.params.sigma_f = sigma_f;
  w.params.sigma_g = sigma_g;
  return w;
}

// A unit cube's surface, `points` samples spread uniformly over its 6 faces, moved along the
// face normal by Gaussian noise of 0.1 spacings, with normals tilted by about 15 degrees: sharp
// 90-degree edges everywhere, as in a scanned machined part.
Workload noisy_cube(const std::string& name, std::size_t points, double sigma_f, double sigma_g) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u01(0, 1);
  std::uniform_int_distribution<int> face(0, 5);
  const double spacing = std::sqrt(6.0 / double(points));
  std::normal_distribution<double> offset(0, 0.1 * spacing), tilt(0, 15 * geometry::kPi / 180);
  Workload w;
  w.name = name;
  w.source = "synthetic noisy cube";
  for (std::size_t i = 0; i < points; ++i) {
    const int f = face(rng), axis = f / 2;
    const double side = f % 2;  // 0: the face at 0, 1: the face at 1
    Vec3 p{u01(rng), u01(rng), u01(rng)}, n{0, 0, 0}, t = n;
    p[axis] = side + offset(rng) * (side > 0 ? 1 : -1);
    n[axis] = side > 0 ? 1 : -1;
    t[(axis + 1) % 3] = tilt(rng);
    t[(axis + 2) % 3] = tilt(rng);
    const Vec3 m{n[0] + t[0], n[1] + t[1], n[2] + t[2]};
    const double len = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    w.cloud.positions.push_back(p);
    w.cloud.normals.push_back({m[0] / len, m[1] / len, m[2] / len});
  }
  w.params.sigma_f = sigma_f;
  w.params.sigma_g = sigma_g;
  return w;
}

}  // namespace

Workload make_workload(const std::string& name, const std::string& shared_data_dir) {
  if (name == "face") return synthetic(name, 75000, 4, 0.5);
  if (name == "dog") return synthetic(name, 400000, 8, 0.5);
  if (name == "cube") return noisy_cube(name, 400000, 8, 0.5);
  if (name == "big") return synthetic(name, 2000000, 8, 0.5);
  if (name == "stray") {  // the face with one stray point 1e9 away: its time should be the face's
    Workload w = synthetic(name, 75000, 4, 0.5);
    w.source += ", one point 1e9 away";
    w.cloud.positions.push_back({1e9, 0, 3e8});
    w.cloud.normals.push_back({0, 0, 1});
    return w;
  }
  if (name.rfind("sweep-", 0) == 0) return synthetic(name, std::stoul(name.substr(6)), 4, 0.5);
  if (name == "bunny") {
    const std::string path = shared_data_dir + "/bunny_scans_merged.ply";
    if (!std::ifstream(path)) return {};
    Workload w;
    w.name = name;
    w.source = "bunny_scans_merged.ply, PCA normals (k 16, mst)";
    w.cloud = read_point_file(path).cloud();
    w.cloud.normals = estimate_normals(w.cloud.positions);
    w.params.sigma_f = 4;
    w.params.sigma_g = 0.5;
    return w;
  }
  return {};
}

}  // namespace pnf::bench
