#include "bench_workloads.hpp"

#include <fstream>

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

}  // namespace

Workload make_workload(const std::string& name, const std::string& shared_data_dir) {
  if (name == "face") return synthetic(name, 75000, 4, 0.5);
  if (name == "dog") return synthetic(name, 400000, 8, 0.5);
  if (name == "big") return synthetic(name, 2000000, 8, 0.5);
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
