// The subcommands of pnf; each file cmd_<name>.cpp registers one.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

#include "pnf/point_cloud.hpp"
#include "pnf/render.hpp"

namespace pnf::cli {

struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;  // returns the exit code
};

Command add_filter_command(CLI::App& parent);
Command add_devices_command(CLI::App& parent);
Command add_info_command(CLI::App& parent);
Command add_estimate_command(CLI::App& parent);
Command add_demo_command(CLI::App& parent);
Command add_render_command(CLI::App& parent);
Command add_compare_command(CLI::App& parent);

// The flags render and compare share (defined in cmd_render.cpp): image size, view, light,
// surfel size, error scale. Size, radius scale and error scale are bound straight to `options`,
// whose defaults are the library's.
struct RenderFlags {
  RenderOptions options;
  std::string view;   // "AZIMUTH,ELEVATION" in degrees, or empty for the default
  std::string light;  // "X,Y,Z" in camera coordinates, or empty for the default
  bool quiet = false;
  void add_to(CLI::App& app, bool panel_size);
  // `options` with view and light applied, validated; throws pnf::Error(invalid_argument) naming
  // the flag and its value.
  RenderOptions parsed() const;
};

// Throws pnf::Error(invalid_argument) unless `path` ends in .png (any case).
void check_png_extension(const std::string& path);

// Reads the point file at `path` (`role` names it in messages, e.g. "IN"); throws
// pnf::Error(invalid_input) when it has no normals.
PointCloud read_cloud_with_normals(const std::string& path, const std::string& role);

// Mean and largest angle in degrees between normals of the same index (both N long, non-zero).
struct AngleStats {
  double mean = 0, max = 0;
};
AngleStats angle_stats(const std::vector<Vec3>& a, const std::vector<Vec3>& b);

// Throws pnf::Error(invalid_argument) when `path` does not end in a format pnf can write,
// so a run fails before the work rather than after it.
void check_output_extension(const std::string& path);

// Throws pnf::Error(invalid_argument) when `out` names the same file as `in` and `in_place` is
// false: the input is never overwritten unless asked.
void check_not_overwriting_input(const std::string& in, const std::string& out, bool in_place);

}  // namespace pnf::cli
