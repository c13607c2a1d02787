#include <algorithm>
#include <cstdio>
#include <cstring>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "pnf/bounding_box.hpp"
#include "pnf/png.hpp"
#include "pnf/render.hpp"

namespace pnf::cli {
namespace {

// Grey of the one-pixel line between panels: visible on white, quieter than the model.
constexpr unsigned char kSeparator = 200;

struct CompareFlags {
  std::string a, b, out, mode = "shaded";
  bool error_panel = false;
  RenderFlags render;
};

// The smallest box holding both clouds (an empty cloud adds nothing).
BoundingBox union_bounds(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  if (a.empty()) return bounding_box(b);
  if (b.empty()) return bounding_box(a);
  return bounding_box(a).united(bounding_box(b));
}

// Copies `panel` into `sheet` with its left edge at column x0, then draws the separator at x0
// (except for the first panel).
void paste(Image& sheet, const Image& panel, int x0) {
  for (int y = 0; y < panel.height; ++y) {
    std::memcpy(&sheet.rgb[3 * (std::size_t(y) * sheet.width + x0)], &panel.rgb[3 * std::size_t(y) * panel.width],
                3 * std::size_t(panel.width));
    if (x0 > 0) std::memset(&sheet.rgb[3 * (std::size_t(y) * sheet.width + x0)], kSeparator, 3);
  }
}

int run_compare(const CompareFlags& flags) {
  Stage stage = Stage::reading;
  return guarded(stage, [&] {
    RenderOptions options = flags.render.parsed();
    options.mode = flags.mode == "normals" ? RenderMode::normals : RenderMode::shaded;
    check_png_extension(flags.out);
    PointCloud a = read_cloud_with_normals(flags.a, "A");
    PointCloud b = read_cloud_with_normals(flags.b, "B");
    if (flags.error_panel && a.size() != b.size()) {
      throw Error(ErrorCode::invalid_input, "A " + flags.a + " has " + std::to_string(a.size()) + " points but B " +
                                                flags.b + " has " + std::to_string(b.size()) +
                                                "; the error panel compares normals of the same index");
    }
    stage = Stage::running;
    // One camera for every panel: the union of both boxes, given to each render as its frame.
    options.frame = union_bounds(a.positions, b.positions);
    std::vector<Image> panels = {render_points(a, options), render_points(b, options)};
    if (flags.error_panel) {
      RenderOptions error = options;
      error.mode = RenderMode::error;
      // The bar is added to the panel's width, so the points get the same drawing area (and
      // camera) as in the other panels.
      error.width = options.width + options.colour_bar_width;
      panels.push_back(render_points(a, b.normals, error));
    }
    Image sheet;
    sheet.height = options.height;
    for (const Image& panel : panels) sheet.width += panel.width;
    sheet.rgb.assign(3 * std::size_t(sheet.width) * std::size_t(sheet.height), 255);
    int x0 = 0;
    for (const Image& panel : panels) {
      paste(sheet, panel, x0);
      x0 += panel.width;
    }
    stage = Stage::writing;
    write_png(flags.out, sheet);
    if (!flags.render.quiet) {
      std::fprintf(stderr, "pnf compare: %zu and %zu points, %d x %d pixels", a.size(), b.size(), sheet.width,
                   sheet.height);
      if (a.size() == b.size()) {
        AngleStats stats = angle_stats(a.normals, b.normals);
        std::fprintf(stderr, ", angle between the normals mean %.2f deg, max %.2f deg", stats.mean, stats.max);
      }
      std::fprintf(stderr, "\n  wrote %s\n", flags.out.c_str());
    }
    return int(kOk);
  });
}

}  // namespace

Command add_compare_command(CLI::App& parent) {
  auto flags = std::make_shared<CompareFlags>();
  CLI::App* app = parent.add_subcommand(
      "compare", "Draw two point models side by side from the same camera, optionally with their normals' angle");
  app->add_option("A", flags->a, "left model: point file with normals")->required();
  app->add_option("B", flags->b, "right model: point file with normals")->required();
  app->add_option("OUT", flags->out, "the picture, .png")->required();
  app->add_option("--mode", flags->mode, "panels A and B: shaded (default) or normals (colour = n * 0.5 + 0.5)")
      ->check(CLI::IsMember({"shaded", "normals"}));
  app->add_flag("--error-panel", flags->error_panel,
                "add a third panel: A's points coloured by the angle between A's and B's normals (same count, same "
                "order), with a colour bar in degrees");
  flags->render.add_to(*app, true);
  return {app, [flags] { return run_compare(*flags); }};
}

}  // namespace pnf::cli
