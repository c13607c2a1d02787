#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "pnf/estimate_normals.hpp"
#include "pnf/point_file.hpp"
#include "pnf/point_file_header.hpp"

namespace pnf::cli {
namespace {

struct EstimateFlags {
  std::string in, out;
  EstimateParams params;
  std::string orient;  // empty: viewpoint for a PCD input (toward its VIEWPOINT), else mst
  std::vector<double> viewpoint;
  bool ascii = false, quiet = false, in_place = false;
  std::string pcd_data;
};

int run_estimate(const EstimateFlags& flags) {
  Stage stage = Stage::reading;
  return guarded(stage, [&] {
    EstimateParams params = flags.params;
    if (!flags.orient.empty()) params.orientation = parse_orientation(flags.orient);
    if (!flags.viewpoint.empty()) params.viewpoint = {flags.viewpoint[0], flags.viewpoint[1], flags.viewpoint[2]};
    params.validate();
    check_output_extension(flags.out);
    check_write_options(flags.out, write_options(flags.ascii, flags.pcd_data));
    check_not_overwriting_input(flags.in, flags.out, flags.in_place);
    ReadOptions read;
    read.check_normals = false;  // replaced below; PCL leaves NaN normals on points with few neighbours
    PointFile file = read_point_file(flags.in, read);
    const PcdHeader* pcd = file.pcd_header();
    if (flags.orient.empty() && pcd) {
      // As PCL does: a scan's normals face the sensor, whose origin the VIEWPOINT line gives.
      params.orientation = Orientation::viewpoint;
      if (flags.viewpoint.empty()) params.viewpoint = {pcd->viewpoint[0], pcd->viewpoint[1], pcd->viewpoint[2]};
      params.validate();
    }
    stage = Stage::running;
    auto start = std::chrono::steady_clock::now();
    // A `curvature` property (PCL's NormalEstimation writes one beside the normals) gets the
    // surface variation of the same fits, as PCL computes it, rather than keeping stale values.
    const bool curvature = file.has_scalar_property("curvature");
    std::vector<double> variation;
    std::vector<Vec3> normals =
        curvature ? estimate_normals(file.cloud().positions, variation, params, progress_bar(flags.quiet))
                  : estimate_normals(file.cloud().positions, params, progress_bar(flags.quiet));
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stage = Stage::writing;
    bool replaced = file.has_normals();
    file.set_normals(normals);
    if (curvature) file.set_scalar_property("curvature", variation);
    write_point_file(flags.out, file, write_options(flags.ascii, flags.pcd_data));
    if (!flags.quiet) {
      // estimate_normals clamps k to N (N >= 3 here, or it would have thrown).
      const std::size_t k = std::min(std::size_t(params.k), normals.size());
      std::fprintf(stderr,
                   "pnf estimate: %zu points, PCA over %zu nearest points (itself included), oriented by %s, "
                   "%.2f s%s\n",
                   normals.size(), k, to_string(params.orientation), seconds,
                   replaced ? " (replaced the file's normals)" : "");
      if (curvature) std::fprintf(stderr, "  curvature    the surface variation of each fit, as PCL computes it\n");
      if (file.valid_count() != file.size()) {
        std::fprintf(stderr, "  %zu invalid (NaN) points left out, kept in place with NaN normals\n",
                     file.size() - file.valid_count());
      }
      std::fprintf(stderr, "  wrote %s\n", flags.out.c_str());
    }
    return int(kOk);
  });
}

}  // namespace

Command add_estimate_command(CLI::App& parent) {
  auto flags = std::make_shared<EstimateFlags>();
  CLI::App* app = parent.add_subcommand(
      "estimate",
      "Estimate oriented normals (PCA over the k nearest points) and, into a curvature property where the file "
      "has one, PCL's surface variation of each fit");
  app->add_option("IN", flags->in, "input point file (.ply, .pcd, .xyz, .xyzn, .pwn)")->required();
  app->add_option("OUT", flags->out, "output file; the format follows its extension")->required();
  app->add_option("--k", flags->params.k,
                  "points in each fit, the point itself included (as PCL's -k and Open3D's KNN count), at least 3")
      ->capture_default_str();  // EstimateParams{}
  app->add_option("--orient", flags->orient,
                  "mst: propagate over a minimum spanning tree (default); outward: away from the centroid; "
                  "viewpoint: toward --viewpoint (the default for a .pcd IN, toward its VIEWPOINT origin, as PCL "
                  "does)")
      ->check(CLI::IsMember({"mst", "outward", "viewpoint"}));
  app->add_option("--viewpoint", flags->viewpoint,
                  "sensor position X,Y,Z for --orient viewpoint (default: a .pcd IN's VIEWPOINT origin, else 0,0,0)")
      ->expected(3)
      ->delimiter(',');
  app->add_flag("--ascii", flags->ascii, "write ascii PLY (default: binary little endian)");
  add_pcd_data_option(*app, flags->pcd_data);
  app->add_flag("--in-place", flags->in_place, "allow OUT to be IN (the file is replaced atomically)");
  app->add_flag("-q,--quiet", flags->quiet, "print nothing but errors");
  return {app, [flags] { return run_estimate(*flags); }};
}

}  // namespace pnf::cli
