#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "pnf/mean_radius.hpp"
#include "pnf/point_file.hpp"
#include "pnf/point_file_header.hpp"

namespace pnf::cli {
namespace {

// Normals within this of length 1 count as unit: float32 storage rounds at about 1e-7.
constexpr double kUnitTolerance = 1e-5;

void print_pcd(const PcdHeader& pcd) {
  std::printf("  format       pcd %s, DATA %s\n", pcd.version.c_str(), to_string(pcd.data));
  for (const std::string& c : pcd.comments) std::printf("  comment      %s\n", c.c_str());
  std::printf("  fields      ");
  for (const PcdField& f : pcd.fields) {
    std::printf(" %s(%c%u", f.name.c_str(), f.type, f.size);
    if (f.count != 1) std::printf(" x%zu", f.count);
    std::printf(")");
  }
  std::printf("\n");
  if (pcd.height > 1)
    std::printf("  organised    %zu x %zu (WIDTH x HEIGHT)\n", pcd.width, pcd.height);
  else
    std::printf("  organised    no (WIDTH %zu, HEIGHT 1)\n", pcd.width);
  const auto& v = pcd.viewpoint;
  std::printf("  viewpoint    origin %.6g %.6g %.6g, orientation (w x y z) %.6g %.6g %.6g %.6g\n", v[0], v[1], v[2],
              v[3], v[4], v[5], v[6]);
}

int run_info(const std::string& path) {
  Stage stage = Stage::reading;
  return guarded(stage, [&] {
    ReadOptions read;
    read.check_normals = false;  // counted below rather than refused: info describes any file
    PointFile file = read_point_file(path, read);
    const PlyHeader& header = file.header();
    std::printf("%s\n", path.c_str());
    const PcdHeader* pcd = file.pcd_header();
    if (pcd) {
      print_pcd(*pcd);
    } else if (file.source_format() == PointFileFormat::ply) {
      std::printf("  format       ply %s\n", to_string(header.encoding));
    } else {
      std::printf("  format       text (x y z%s per line)\n", file.has_normals() ? " nx ny nz" : "");
    }
    for (const PlyComment& c : header.comments) std::printf("  %-12s %s\n", c.keyword.c_str(), c.text.c_str());
    for (const PlyElement& e : pcd ? std::vector<PlyElement>{} : header.elements) {
      std::printf("  element      %s %zu:", e.name.c_str(), e.count);
      for (const PlyProperty& p : e.properties) {
        if (p.is_list)
          std::printf(" %s(list %s %s)", p.name.c_str(), p.count_type_name.c_str(), p.type_name.c_str());
        else
          std::printf(" %s(%s)", p.name.c_str(), p.type_name.c_str());
      }
      std::printf("\n");
    }
    PointCloud cloud = file.cloud();
    if (pcd || file.valid_count() != file.size()) {
      std::printf("  points       %zu valid, %zu invalid (NaN coordinates: kept in place, left out of estimates)\n",
                  cloud.size(), file.size() - cloud.size());
    } else {
      std::printf("  points       %zu\n", cloud.size());
    }
    if (cloud.size() == 0) return int(kOk);
    Vec3 lo = cloud.positions[0], hi = cloud.positions[0];
    for (const Vec3& p : cloud.positions)
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], p[k]);
        hi[k] = std::max(hi[k], p[k]);
      }
    std::printf("  bounds       [%.6g %.6g %.6g] .. [%.6g %.6g %.6g]\n", lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
    if (cloud.has_radii()) {
      double sum = 0;
      for (double r : cloud.radii) sum += r;
      std::printf("  mean radius  %.6g (radius property)\n", sum / double(cloud.size()));
    } else if (const double estimated = estimate_mean_radius(cloud.positions); estimated > 0) {
      std::printf("  mean radius  %.6g (estimated: median mean distance to the 4 nearest points)\n", estimated);
    } else {
      // As pnf filter then refuses to run without --radius or absolute units.
      std::printf(
          "  mean radius  none: cannot be estimated from %zu points (it needs at least 5, not most at one "
          "place); give pnf filter --radius or absolute units\n",
          cloud.size());
    }
    if (!cloud.has_normals()) {
      std::printf("  normals      none (run pnf estimate)\n");
    } else {
      std::size_t off = 0, bad = 0, missing = 0;
      for (const Vec3& n : cloud.normals) {
        const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (std::isnan(n[0]) && std::isnan(n[1]) && std::isnan(n[2]))
          ++missing;
        else if (!std::isfinite(length) || length == 0)
          ++bad;
        else
          off += std::fabs(length - 1) > kUnitTolerance;
      }
      // A NaN normal is a point without a normal in PLY and PCD (PointFile), an error in text.
      const bool text = file.source_format() != PointFileFormat::ply && !pcd;
      if (text) bad += missing;
      if (const PlyProperty* integer = file.integer_normal_property())
        std::printf(
            "  normals      yes, declared '%s', an integer type: pnf filter and pnf estimate cannot write "
            "normals into them (convert them to float first)",
            integer->type_name.c_str());
      else if (bad > 0)
        std::printf(
            "  normals      yes, %zu NaN, infinite or zero (pnf filter refuses them; pnf estimate replaces "
            "every normal)",
            bad);
      else if (off == 0)
        std::printf("  normals      yes, unit length");
      else
        std::printf("  normals      yes, %zu not unit length (pnf filter normalises them)", off);
      if (missing > 0 && !text)
        std::printf("; %zu points without normals (NaN, as PCL leaves them: pnf filter keeps them as they were)",
                    missing);
      std::printf("\n");
    }
    return int(kOk);
  });
}

}  // namespace

Command add_info_command(CLI::App& parent) {
  auto path = std::make_shared<std::string>();
  CLI::App* app =
      parent.add_subcommand("info", "Describe a point file: elements, properties, bounds, spacing, normals");
  app->add_option("IN", *path, "point file (.ply, .pcd, .xyz, .xyzn, .pwn)")->required();
  return {app, [path] { return run_info(*path); }};
}

}  // namespace pnf::cli
