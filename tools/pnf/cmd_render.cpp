#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <sstream>

#include "cli_common.hpp"
#include "commands.hpp"
#include "pnf/angle.hpp"
#include "pnf/png.hpp"
#include "pnf/point_file.hpp"
#include "pnf/render.hpp"

namespace pnf::cli {
namespace {

// Splits "a,b,c" into exactly `count` finite numbers; false when it is anything else.
bool parse_numbers(const std::string& text, std::size_t count, std::vector<double>& out) {
  out.clear();
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) {
    const char* begin = item.c_str();
    char* end = nullptr;
    const double value = std::strtod(begin, &end);
    while (end && std::isspace(static_cast<unsigned char>(*end))) ++end;
    if (end == begin || *end != '\0' || !std::isfinite(value)) return false;
    out.push_back(value);
  }
  return out.size() == count && (text.empty() || text.back() != ',');
}

RenderMode parse_mode(const std::string& mode) {
  if (mode == "normals") return RenderMode::normals;
  if (mode == "error") return RenderMode::error;
  return RenderMode::shaded;
}

struct RenderCommandFlags {
  std::string in, out, truth, mode = "shaded";
  RenderFlags render;
};

int run_render(const RenderCommandFlags& flags) {
  Stage stage = Stage::reading;
  return guarded(stage, [&] {
    RenderOptions options = flags.render.parsed();
    options.mode = parse_mode(flags.mode);
    options.validate();
    if (options.mode == RenderMode::error && flags.truth.empty()) {
      throw Error(ErrorCode::invalid_argument,
                  "--mode error needs --truth GT: a point file whose normals (same count, same order) are the truth");
    }
    if (options.mode != RenderMode::error && !flags.truth.empty()) {
      throw Error(ErrorCode::invalid_argument, "--truth is used only with --mode error");
    }
    check_png_extension(flags.out);
    PointCloud cloud = read_cloud_with_normals(flags.in, "IN");
    std::vector<Vec3> truth;
    if (!flags.truth.empty()) {
      truth = read_cloud_with_normals(flags.truth, "--truth").normals;
      if (truth.size() != cloud.size()) {
        throw Error(ErrorCode::invalid_input, "--truth " + flags.truth + " has " + std::to_string(truth.size()) +
                                                  " points but " + flags.in + " has " + std::to_string(cloud.size()) +
                                                  "; the error is taken between normals of the same index");
      }
    }
    stage = Stage::running;
    Image image = render_points(cloud, truth, options);
    stage = Stage::writing;
    write_png(flags.out, image);
    if (!flags.render.quiet) {
      std::fprintf(stderr, "pnf render: %zu points, %d x %d pixels", cloud.size(), image.width, image.height);
      if (!truth.empty()) {
        AngleStats stats = angle_stats(cloud.normals, truth);
        std::fprintf(stderr, ", angle to truth mean %.2f deg, max %.2f deg", stats.mean, stats.max);
      }
      std::fprintf(stderr, "\n  wrote %s\n", flags.out.c_str());
    }
    return int(kOk);
  });
}

}  // namespace

void RenderFlags::add_to(CLI::App& app, bool panel_size) {
  const std::string per = panel_size ? " of each panel" : "";
  // Numeric defaults in the help are RenderOptions{}'s, captured, never restated.
  app.add_option("--width", options.width, "image width" + per + " in pixels, 1 to 16384")->capture_default_str();
  app.add_option("--height", options.height, "image height" + per + " in pixels, 1 to 16384")->capture_default_str();
  app.add_option("--view", view,
                 "AZIMUTH,ELEVATION in degrees (default 0,0: looking down -z with +y up; azimuth turns about "
                 "+y, elevation -90..90 raises the camera)");
  app.add_option("--light", light,
                 "X,Y,Z direction toward the light in camera coordinates: x right, y up, z toward the viewer "
                 "(default -0.5,0.6,1)");
  app.add_option("--radius-scale", options.radius_scale,
                 "surfel radius as a multiple of the point spacing (the radius property, else the spacing "
                 "estimate the filter uses); the default leaves no holes in a uniformly sampled surface")
      ->capture_default_str();
  app.add_option("--error-max", options.error_max_degrees,
                 "error colours: angles at or above this many degrees get the top colour")
      ->capture_default_str();
  app.add_flag("-q,--quiet", quiet, "print nothing but errors");
}

RenderOptions RenderFlags::parsed() const {
  RenderOptions o = options;
  std::vector<double> numbers;
  if (!view.empty()) {
    if (!parse_numbers(view, 2, numbers)) {
      throw Error(ErrorCode::invalid_argument,
                  "--view '" + view + "': expected AZIMUTH,ELEVATION in degrees, e.g. --view 30,20");
    }
    o.azimuth_degrees = numbers[0];
    o.elevation_degrees = numbers[1];
  }
  if (!light.empty()) {
    if (!parse_numbers(light, 3, numbers)) {
      throw Error(ErrorCode::invalid_argument,
                  "--light '" + light + "': expected X,Y,Z (camera coordinates), e.g. --light -0.5,0.6,1");
    }
    o.light = {numbers[0], numbers[1], numbers[2]};
  }
  o.validate();
  return o;
}

void check_png_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".png") throw Error(ErrorCode::invalid_argument, path + ": the picture is written as PNG; name it .png");
}

PointCloud read_cloud_with_normals(const std::string& path, const std::string& role) {
  PointCloud cloud = read_point_file(path).cloud();
  if (!cloud.has_normals() && cloud.size() > 0) {
    throw Error(ErrorCode::invalid_input,
                role + " " + path + " has no normals to draw; estimate them first (pnf estimate)");
  }
  return cloud;
}

AngleStats angle_stats(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  AngleStats stats;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double angle = angle_degrees(a[i], b[i]);
    stats.mean += angle;
    stats.max = std::max(stats.max, angle);
  }
  if (!a.empty()) stats.mean /= double(a.size());
  return stats;
}

Command add_render_command(CLI::App& parent) {
  auto flags = std::make_shared<RenderCommandFlags>();
  CLI::App* app = parent.add_subcommand("render", "Draw a point model as lit surfels into a PNG picture");
  app->add_option("IN", flags->in, "point file with normals (.ply, .pcd, .xyz, .xyzn, .pwn)")->required();
  app->add_option("OUT", flags->out, "the picture, .png")->required();
  app->add_option("--mode", flags->mode,
                  "shaded: grey, lit from the normals (default); normals: colour = n * 0.5 + 0.5; error: colour by "
                  "the angle to the normals of --truth, with a colour bar")
      ->check(CLI::IsMember({"shaded", "normals", "error"}));
  app->add_option("--truth", flags->truth,
                  "for --mode error: point file with the true normals, same points in the same order");
  flags->render.add_to(*app, false);
  return {app, [flags] { return run_render(*flags); }};
}

}  // namespace pnf::cli
