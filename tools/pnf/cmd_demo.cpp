#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "pnf/angle.hpp"
#include "pnf/point_file.hpp"
#include "pnf/synthetic_shapes.hpp"

namespace pnf::cli {
namespace {

struct DemoFlags {
  std::size_t points = 100000;
  std::string dir = "pnf-demo";
  ScanNoise noise;
  DeviceFlags device;
};

struct ErrorStats {
  double mean = 0, median = 0, p90 = 0;
};

ErrorStats error_stats(const std::vector<Vec3>& normals, const std::vector<Vec3>& truth) {
  std::vector<double> a(normals.size());
  for (std::size_t i = 0; i < a.size(); ++i) a[i] = angle_degrees(normals[i], truth[i]);
  ErrorStats s;
  for (double v : a) s.mean += v / double(a.size());
  std::sort(a.begin(), a.end());
  s.median = a[a.size() / 2];
  s.p90 = a[a.size() * 9 / 10];
  return s;
}

int run_demo(const DemoFlags& flags) {
  Stage stage = Stage::running;
  return guarded(stage, [&] {
    SyntheticCloud house = make_scanned_house(flags.points, flags.noise);
    NormalFilter filter(flags.device.options());
    // The library's defaults (the paper's settings), printed from the same value below.
    const FilterParams params{};
    FilterResult result = filter.run(house.cloud, params, progress_bar(false));
    // Written only after the run, so that a device failure leaves no folder and no half demo.
    stage = Stage::writing;
    std::error_code ec;
    std::filesystem::create_directories(flags.dir, ec);
    if (ec) throw Error(ErrorCode::io, "cannot create the folder '" + flags.dir + "': " + ec.message());
    const std::string noisy = flags.dir + "/house_noisy.ply", filtered = flags.dir + "/house_filtered.ply";
    write_point_file(noisy, PointFile(house.cloud));
    PointFile out(house.cloud);
    out.set_normals(result.normals);
    write_point_file(filtered, out);

    const FilterSummary& s = result.summary;
    ErrorStats before = error_stats(house.cloud.normals, house.true_normals);
    ErrorStats after = error_stats(result.normals, house.true_normals);
    std::size_t better = 0;
    for (std::size_t i = 0; i < house.cloud.size(); ++i) {
      better += angle_degrees(result.normals[i], house.true_normals[i]) <
                angle_degrees(house.cloud.normals[i], house.true_normals[i]);
    }
    std::printf("pnf demo: a synthetic scanned house, %zu points, spacing %.3g, sharp 90 and 135 degree edges\n",
                house.cloud.size(), house.spacing);
    std::printf("  noise        positions %.2g spacings along the normal, normals %.3g degrees per axis\n",
                flags.noise.position, flags.noise.normal_degrees);
    std::printf("  filter       paper defaults: sigma_f %g, sigma_g %g %s (%.3g, %.3g model units), %d passes\n",
                params.sigma_f, params.sigma_g, params.units == Units::radius ? "mean radii" : "model units", s.sigma_f,
                s.sigma_g, params.iterations);
    std::printf("  device       %s\n", s.device.c_str());
    std::printf("  neighbours   %.1f per point; lists %.2f s; passes", s.neighbours_mean, s.neighbour_seconds);
    for (double t : s.pass_seconds) std::printf(" %.3f", t);
    std::printf(" s\n");
    std::printf("  error to the true normals (degrees)   mean   median   90th pct\n");
    std::printf("    input                             %6.2f   %6.2f   %6.2f\n", before.mean, before.median,
                before.p90);
    std::printf("    filtered                          %6.2f   %6.2f   %6.2f\n", after.mean, after.median, after.p90);
    std::printf("  improved     %.1f%% of points; mean error %.1fx smaller\n",
                100.0 * double(better) / double(house.cloud.size()), before.mean / after.mean);
    std::printf("  wrote        %s and %s\n", noisy.c_str(), filtered.c_str());
    return int(kOk);
  });
}

}  // namespace

Command add_demo_command(CLI::App& parent) {
  auto flags = std::make_shared<DemoFlags>();
  CLI::App* app = parent.add_subcommand(
      "demo", "Make a noisy synthetic scan with sharp edges, filter it, and report the improvement");
  app->add_option("--points", flags->points, "about how many points")
      ->capture_default_str()
      ->check(CLI::Range(100, 100000000));
  app->add_option("--dir", flags->dir, "folder for house_noisy.ply and house_filtered.ply")->capture_default_str();
  app->add_option("--position-noise", flags->noise.position, "in sample spacings")
      ->capture_default_str()
      ->check(finite_non_negative());
  app->add_option("--normal-noise", flags->noise.normal_degrees, "in degrees")
      ->capture_default_str()
      ->check(finite_non_negative());
  app->add_option("--seed", flags->noise.seed, "random seed")->capture_default_str();
  flags->device.add_to(*app);
  return {app, [flags] { return run_demo(*flags); }};
}

}  // namespace pnf::cli
