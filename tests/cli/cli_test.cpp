// The pnf tool end to end: `filter` on a real scan against the library run in this process,
// `estimate` then `filter` on shapes with known normals, --in-place, the summary and progress
// display, `devices`, `info`, `demo` and every subcommand's --help. The failures are in
// cli_errors_test.cpp. Runs the built binary (PNF_CLI_PATH); skipped when it was not built.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_test_support.hpp"
#include "pnf/device.hpp"
#include "pnf/normal_filter.hpp"
#include "pnf/point_file.hpp"
#include "pnf/synthetic_shapes.hpp"
#include "test_backends.hpp"
#include "test_clouds.hpp"

namespace pnf::test {
namespace {

// Share of points whose normal must face the same side as the true one after `estimate`
// (the issue's bar). Misses are allowed only right at sharp edges, where a neighbourhood
// straddles two faces.
constexpr double kMinOrientedShare = 0.99;

// The OpenCL filter when a device is found, else the reference, and the --backend that picks
// the same in the tool. Both then run the same code on the same device (the tool inherits
// PNF_DEVICE), so their normals agree exactly.
struct SameBackend {
  NormalFilter* filter = nullptr;
  std::string flag;
};

SameBackend same_backend() {
  std::string why;
  if (NormalFilter* f = opencl_filter(why)) return {f, "opencl"};
  if (std::getenv("PNF_DEVICE")) ADD_FAILURE() << "PNF_DEVICE is set but: " << why;
  return {reference_filter(), "reference"};
}

// A jittered 20 x 20 grid in z = 0 with normals tilted about 10 degrees from +z.
PointCloud noisy_grid() {
  constexpr double kTiltDegrees = 10;
  PointCloud c = jittered_grid(20, 1.0, 0.2, 7);
  std::mt19937 rng(8);
  for (Vec3& n : c.normals) n = jitter_normal(n, kTiltDegrees, rng);
  return c;
}

double share_facing(const std::vector<Vec3>& normals, const std::vector<Vec3>& truth) {
  std::size_t agree = 0;
  for (std::size_t i = 0; i < normals.size(); ++i) agree += dot(normals[i], truth[i]) > 0;
  return double(agree) / double(normals.size());
}

std::vector<Vec3> read_normals(const std::string& file) { return read_point_file(file).cloud().normals; }

std::string format_g(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

// ---- filter -------------------------------------------------------------------------------

// Armadillo.ply: 38,294 vertices with float normals and an empty face element. The tool and the
// library run the same backend on the same device with the same defaults, so the tool's normals
// must be the library's rounded to float (the file's type for nx ny nz), bit for bit: any
// difference means the tool changed a parameter, the data or the order on the way.
TEST_F(CliTest, FilterOnArmadilloEqualsTheLibrary) {
  const std::string data = shared_data_dir();
  const std::string model = data + "/Armadillo.ply";
  if (data.empty() || !std::filesystem::exists(model)) {
    GTEST_SKIP() << "no shared data: " << model << " is absent (set PNF_SHARED_DATA to the folder of Armadillo.ply)";
  }
  const SameBackend backend = same_backend();
  const std::string out = path("armadillo_filtered.ply");
  const CliRun r = run({"filter", model, out, "--backend", backend.flag});
  ASSERT_EQ(r.exit_code, 0) << r.describe();

  const PointFile input = read_point_file(model);
  const FilterResult expected = backend.filter->run(input.cloud());
  const PointFile output = read_point_file(out);
  ASSERT_EQ(output.size(), input.size());
  ASSERT_EQ(output.header().elements.size(), input.header().elements.size()) << "the face element was lost";
  EXPECT_EQ(output.element_values(0).size(), input.element_values(0).size());
  const PointCloud got = output.cloud();
  EXPECT_EQ(got.positions, input.cloud().positions);
  std::size_t differing = 0;
  double worst_degrees = 0;
  for (std::size_t i = 0; i < got.size(); ++i) {
    bool same = true;
    for (int k = 0; k < 3; ++k) same = same && float(expected.normals[i][k]) == float(got.normals[i][k]);
    if (!same) {
      if (differing == 0) {
        ADD_FAILURE() << "vertex " << i << ": tool (" << got.normals[i][0] << ", " << got.normals[i][1] << ", "
                      << got.normals[i][2] << ") library (" << expected.normals[i][0] << ", " << expected.normals[i][1]
                      << ", " << expected.normals[i][2] << ")";
      }
      ++differing;
      worst_degrees = std::max(worst_degrees, angle_deg(got.normals[i], expected.normals[i]));
    }
  }
  EXPECT_EQ(differing, 0u) << "normals differ; worst by " << worst_degrees << " degrees";

  // The summary reports what the library reported.
  const FilterSummary& s = expected.summary;
  EXPECT_TRUE(contains(r.err, "38294 points")) << r.err;
  EXPECT_EQ(s.radius_source, RadiusSource::estimate);
  EXPECT_TRUE(
      contains(r.err, "mean radius  " + format_g("%.6g", s.mean_radius) + " (" + to_string(s.radius_source) + ")"))
      << r.err;
  EXPECT_TRUE(contains(r.err, "sigma_f      " + format_g("%.6g", s.sigma_f) + " model units")) << r.err;
  EXPECT_TRUE(contains(r.err, "sigma_g " + format_g("%.6g", s.sigma_g))) << r.err;
  EXPECT_TRUE(contains(r.err, "max " + std::to_string(s.neighbours_max) + " per point")) << r.err;
  EXPECT_TRUE(contains(r.err, format_g("mean %.1f", s.neighbours_mean))) << r.err;
  EXPECT_TRUE(contains(r.err, s.device)) << r.err;
  EXPECT_TRUE(contains(r.err, "passes       4:")) << r.err;
  // stderr is a file here, not a terminal: no progress bar.
  EXPECT_FALSE(contains(r.err, "\r")) << r.err;
}

// The flags reach the library: absolute units, sigmas and passes as given, the same normals as
// the reference run in process with those parameters (doubles in the file written from a cloud).
TEST_F(CliTest, FilterFlagsReachTheLibrary) {
  const std::string in = write_cloud("grid.ply", noisy_grid());
  const CliRun r = run({"filter", in, path("out.ply"), "--backend", "reference", "--units", "absolute", "--sigma-f",
                        "1.5", "--sigma-g", "0.25", "--iterations", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  FilterParams params;
  params.units = Units::absolute;
  params.sigma_f = 1.5;
  params.sigma_g = 0.25;
  params.iterations = 2;
  const FilterResult expected = reference_filter()->run(read_point_file(in).cloud(), params);
  EXPECT_EQ(read_normals(path("out.ply")), expected.normals);
  EXPECT_FALSE(contains(r.err, "mean radius")) << "absolute units use no radius\n" << r.err;
  EXPECT_TRUE(contains(r.err, "sigma_f      1.5 model units, sigma_g 0.25 (absolute units)")) << r.err;
  EXPECT_TRUE(contains(r.err, "passes       2:")) << r.err;

  const CliRun given = run({"filter", in, path("given.ply"), "--backend", "reference", "--radius", "0.5"});
  ASSERT_EQ(given.exit_code, 0) << given.describe();
  EXPECT_TRUE(contains(given.err, "mean radius  0.5 (" + std::string(to_string(RadiusSource::given)) + ")"))
      << given.err;
  EXPECT_TRUE(contains(given.err, "sigma_f      2 model units, sigma_g 0.25 (radius units: 4, 0.5)")) << given.err;
}

TEST_F(CliTest, FilterLeavesTheInputAloneAndWritesEachFormat) {
  const std::string in = write_cloud("in.ply", noisy_grid());
  const std::string before = read_whole_file(in);
  const CliRun r = run({"filter", in, path("out.ply"), "--backend", "reference"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_EQ(read_whole_file(in), before) << "the input changed";
  const std::vector<Vec3> truth(400, Vec3{0, 0, 1});
  const std::vector<Vec3> filtered = read_normals(path("out.ply"));
  EXPECT_LT(mean_angle_deg(filtered, truth), mean_angle_deg(read_point_file(in).cloud().normals, truth));

  const CliRun ascii = run({"filter", in, path("out_ascii.ply"), "--backend", "reference", "--ascii", "--quiet"});
  ASSERT_EQ(ascii.exit_code, 0) << ascii.describe();
  EXPECT_EQ(ascii.err, "") << "--quiet prints nothing";
  EXPECT_EQ(read_whole_file(path("out_ascii.ply")).rfind("ply\nformat ascii 1.0\n", 0), 0u);
  EXPECT_EQ(read_normals(path("out_ascii.ply")), filtered);

  const CliRun xyz = run({"filter", in, path("out.xyzn"), "--backend", "reference", "-q"});
  ASSERT_EQ(xyz.exit_code, 0) << xyz.describe();
  EXPECT_EQ(read_normals(path("out.xyzn")), filtered);
  EXPECT_EQ(folder_entries(work_), (std::set<std::string>{"in.ply", "out.ply", "out_ascii.ply", "out.xyzn"}));
}

TEST_F(CliTest, InPlaceReplacesTheInput) {
  const std::string in = write_cloud("in.ply", noisy_grid());
  const PointCloud original = read_point_file(in).cloud();
  const CliRun r = run({"filter", in, in, "--in-place", "--backend", "reference"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const PointCloud replaced = read_point_file(in).cloud();
  EXPECT_EQ(replaced.positions, original.positions);
  EXPECT_EQ(replaced.normals, reference_filter()->run(original).normals);
  EXPECT_EQ(folder_entries(work_), std::set<std::string>{"in.ply"}) << "a temporary file was left";

  const CliRun estimate = run({"estimate", in, in, "--in-place", "-q"});
  ASSERT_EQ(estimate.exit_code, 0) << estimate.describe();
  EXPECT_NE(read_normals(in), replaced.normals);
  EXPECT_EQ(folder_entries(work_), std::set<std::string>{"in.ply"});
}

// PCL's output: NaN normals on valid points with too few neighbours (and an invalid NaN point).
// `filter` keeps those points in place with their NaN normals, leaves them out of every
// neighbourhood (the other normals are the library's on the cloud without them), and keeps the
// organisation.
TEST_F(CliTest, FilterKeepsPointsWithoutNormalsAsTheyWere) {
  const PointCloud grid = noisy_grid();
  const std::set<std::size_t> without_normals = {5, 17, 233}, invalid = {30};
  std::string text =
      "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z normal_x normal_y normal_z\n"
      "SIZE 8 8 8 8 8 8\nTYPE F F F F F F\nCOUNT 1 1 1 1 1 1\nWIDTH 20\nHEIGHT 20\nVIEWPOINT 0 0 0 1 0 0 0\n"
      "POINTS 400\nDATA ascii\n";
  PointCloud kept;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const Vec3& p = grid.positions[i];
    const Vec3& n = grid.normals[i];
    if (invalid.count(i) > 0) {
      text += "nan nan nan nan nan nan\n";
      continue;
    }
    char row[256];
    std::snprintf(row, sizeof row, "%.17g %.17g %.17g ", p[0], p[1], p[2]);
    text += row;
    if (without_normals.count(i) > 0) {
      text += "nan nan nan\n";
      continue;
    }
    std::snprintf(row, sizeof row, "%.17g %.17g %.17g\n", n[0], n[1], n[2]);
    text += row;
    kept.positions.push_back(p);
    kept.normals.push_back(n);
  }
  write_whole_file(path("pcl.pcd"), text);
  const CliRun r = run({"filter", path("pcl.pcd"), path("out.pcd"), "--backend", "reference"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const PointFile out = read_point_file(path("out.pcd"));
  EXPECT_EQ(out.pcd_header()->width, 20u);
  EXPECT_EQ(out.pcd_header()->height, 20u);
  EXPECT_EQ(out.size(), 400u);
  EXPECT_EQ(out.without_normals(), 3u);
  ASSERT_EQ(out.valid_count(), 396u);
  for (std::size_t i = 0; i < out.valid_count(); ++i) {
    EXPECT_EQ(without_normals.count(out.row_of_point(i)) + invalid.count(out.row_of_point(i)), 0u);
  }
  EXPECT_EQ(out.cloud().positions, kept.positions);
  EXPECT_EQ(out.cloud().normals, reference_filter()->run(kept).normals);
}

// The bar is drawn only on a terminal: run through script(1), which gives the tool a
// pseudo-terminal, and the bar's carriage returns and pass count appear.
TEST_F(CliTest, ProgressBarOnlyOnATerminal) {
  if (std::system("command -v script >/dev/null 2>&1") != 0) GTEST_SKIP() << "script(1) is not installed";
  const std::string in = write_cloud("in.ply", noisy_grid());
  const std::string inner = shell_quote(PNF_CLI_PATH) + " filter " + shell_quote(in) + " " +
                            shell_quote(path("out.ply")) + " --backend reference --iterations 3";
  const std::string transcript = (root_ / "terminal.txt").string();
  const std::string command =
      "script -q -e -c " + shell_quote(inner) + " /dev/null >" + shell_quote(transcript) + " 2>&1 </dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0) << read_whole_file(transcript);
  const std::string shown = read_whole_file(transcript);
  EXPECT_TRUE(contains(shown, "pass 3/3")) << shown;
  EXPECT_TRUE(contains(shown, "\r")) << shown;

  const CliRun quiet = run({"filter", in, path("out.ply"), "--backend", "reference", "--iterations", "3"});
  EXPECT_FALSE(contains(quiet.err, "pass 3/3")) << quiet.err;
}

// SIGINT stops the run after the current pass: exit 6, no output, no temporary file. The run
// would take minutes uncancelled; timeout(1) sends SIGINT after 1 s and SIGKILL 10 s later.
TEST_F(CliTest, InterruptCancelsTheRun) {
  constexpr int kExitCancelled = 6;
  if (std::system("command -v timeout >/dev/null 2>&1") != 0) GTEST_SKIP() << "timeout(1) is not installed";
  const std::string in = write_cloud("in.ply", noisy_grid());
  const CliRun r = run({"filter", in, path("out.ply"), "--backend", "reference", "--iterations", "20000"},
                       // 3 s: a loaded machine can take a second just to start the process and
                       // read the file. --foreground: without it timeout signals the child and
                       // then its whole process group, so pnf would see a second SIGINT, which
                       // (like a second Ctrl-C) ends it at once.
                       "timeout --foreground --preserve-status -k 10 -s INT 3");
  EXPECT_EQ(r.exit_code, kExitCancelled) << r.describe();
  EXPECT_TRUE(contains(r.err, "cancelled")) << r.err;
  EXPECT_EQ(folder_entries(work_), std::set<std::string>{"in.ply"});
}

// SIGINT stops `pnf estimate` too (within about 0.2 s, during the k-nearest search or the fits):
// exit 6, no output. 200k points with k = 200 take about 6 s on 2 loaded cores (and some 400 MB);
// timeout(1) sends SIGINT after 2 s, as above.
TEST_F(CliTest, InterruptCancelsAnEstimate) {
  constexpr int kExitCancelled = 6;
  if (std::system("command -v timeout >/dev/null 2>&1") != 0) GTEST_SKIP() << "timeout(1) is not installed";
  PointCloud bare;
  bare.positions = sphere(200000, 1.0, 41).positions;
  const std::string in = write_cloud("in.xyz", bare);
  // Work for well over the 2 s before the interrupt (k 200 took about 2 s alone on an idle 2-core
  // AVX-512 machine, so it could end first); k 400 doubles it and keeps the neighbour table
  // (200k rows of k) at a few hundred MB, under the sanitizers too.
  const CliRun r = run({"estimate", in, path("out.ply"), "--k", "400", "--orient", "outward"},
                       "timeout --foreground --preserve-status -k 10 -s INT 2");
  EXPECT_EQ(r.exit_code, kExitCancelled) << r.describe();
  EXPECT_TRUE(contains(r.err, "cancelled")) << r.err;
  EXPECT_EQ(folder_entries(work_), std::set<std::string>{"in.xyz"});
}

// ---- estimate -----------------------------------------------------------------------------

// The scanned house (sharp 90 and 135 degree edges, noisy positions) without its normals:
// `estimate` (MST orientation) then `filter` keep almost every normal on the outer side.
TEST_F(CliTest, EstimateThenFilterOnTheHouse) {
  const SyntheticCloud house = make_scanned_house(3000);
  PointCloud bare;
  bare.positions = house.cloud.positions;
  const std::string in = write_cloud("house.xyz", bare);
  const CliRun estimate = run({"estimate", in, path("estimated.ply")});
  ASSERT_EQ(estimate.exit_code, 0) << estimate.describe();
  EXPECT_TRUE(contains(estimate.err, "oriented by mst")) << estimate.err;
  const CliRun filter = run({"filter", path("estimated.ply"), path("filtered.ply"), "--backend", "reference"});
  ASSERT_EQ(filter.exit_code, 0) << filter.describe();

  const std::vector<Vec3> estimated = read_normals(path("estimated.ply"));
  const std::vector<Vec3> filtered = read_normals(path("filtered.ply"));
  ASSERT_EQ(filtered.size(), house.true_normals.size());
  EXPECT_GE(share_facing(estimated, house.true_normals), kMinOrientedShare);
  EXPECT_GE(share_facing(filtered, house.true_normals), kMinOrientedShare);
  EXPECT_EQ(read_point_file(path("filtered.ply")).cloud().positions, read_point_file(in).cloud().positions);
}

// A sphere with --orient outward: every normal faces out, and the estimate is close to exact.
TEST_F(CliTest, EstimateOutwardOnASphere) {
  // PCA on 12 neighbours of a 2000-point unit sphere tilts by the curvature across the patch:
  // well under this.
  constexpr double kMaxMeanDegrees = 3;
  const PointCloud truth = sphere(2000, 1.0, 3);
  PointCloud bare;
  bare.positions = truth.positions;
  const std::string in = write_cloud("sphere.ply", bare);
  const CliRun r = run({"estimate", in, path("estimated.ply"), "--orient", "outward", "--k", "12"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_TRUE(contains(r.err, "2000 points, PCA over 12 nearest points (itself included), oriented by outward")) << r.err;
  const std::vector<Vec3> estimated = read_normals(path("estimated.ply"));
  EXPECT_GE(share_facing(estimated, truth.normals), kMinOrientedShare);
  EXPECT_LT(mean_angle_deg(estimated, truth.normals), kMaxMeanDegrees);
  const CliRun filter = run({"filter", path("estimated.ply"), path("filtered.ply"), "--backend", "reference", "-q"});
  ASSERT_EQ(filter.exit_code, 0) << filter.describe();
  EXPECT_GE(share_facing(read_normals(path("filtered.ply")), truth.normals), kMinOrientedShare);
}

// A k beyond the cloud is clamped to N by the library; the summary says what was used.
TEST_F(CliTest, EstimateReportsTheClampedK) {
  write_whole_file(path("five.xyz"), "0 0 0\n1 0 0\n0 1 0\n1 1 0\n0.5 0.5 0\n");
  const CliRun r = run({"estimate", path("five.xyz"), path("out.xyzn"), "--k", "100"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_TRUE(contains(r.err, "5 points, PCA over 5 nearest points")) << r.err;
  EXPECT_EQ(read_normals(path("out.xyzn")), std::vector<Vec3>(5, Vec3{0, 0, 1}));
}

// ---- devices, info, demo, help ------------------------------------------------------------

TEST_F(CliTest, DevicesMarksTheDeviceInUse) {
  const std::vector<DeviceInfo> devices = list_devices();
  if (devices.empty()) {
    if (std::getenv("PNF_DEVICE")) FAIL() << "PNF_DEVICE is set but no OpenCL device is found";
    GTEST_SKIP() << "no OpenCL device (set PNF_DEVICE to make this a failure)";
  }
  const auto marked_lines = [](const std::string& out) {
    std::vector<std::string> marked;
    std::istringstream lines(out);
    for (std::string line; std::getline(lines, line);) {
      if (!line.empty() && line[0] == '*') marked.push_back(line);
    }
    return marked;
  };
  const CliRun r = run({"devices"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  std::vector<std::string> marked = marked_lines(r.out);
  ASSERT_EQ(marked.size(), 1u) << r.out;
  for (const DeviceInfo& d : devices) {
    if (d.selected) {
      EXPECT_EQ(marked[0].rfind("* " + std::to_string(d.platform_index) + ":" + std::to_string(d.device_index), 0), 0u)
          << r.out;
      EXPECT_TRUE(contains(marked[0], d.device_name)) << r.out;
    }
  }

  const DeviceInfo& last = devices.back();
  const std::string spec = std::to_string(last.platform_index) + ":" + std::to_string(last.device_index);
  const CliRun chosen = run({"devices", "--device", spec});
  ASSERT_EQ(chosen.exit_code, 0) << chosen.describe();
  marked = marked_lines(chosen.out);
  ASSERT_EQ(marked.size(), 1u) << chosen.out;
  EXPECT_EQ(marked[0].rfind("* " + spec, 0), 0u) << chosen.out;
  EXPECT_TRUE(contains(chosen.out, "selector: " + spec)) << chosen.out;

  const CliRun from_environment = run({"devices"}, "PNF_DEVICE=" + spec);
  ASSERT_EQ(from_environment.exit_code, 0) << from_environment.describe();
  EXPECT_EQ(marked_lines(from_environment.out), marked);

  const CliRun none = run({"devices", "--device", "no-such-device-xyzzy"});
  EXPECT_EQ(none.exit_code, 4) << none.describe();
  EXPECT_TRUE(marked_lines(none.out).empty()) << none.out;
  EXPECT_TRUE(contains(none.err, "no-such-device-xyzzy")) << none.err;
}

TEST_F(CliTest, InfoDescribesAPlyFile) {
  write_whole_file(path("box.ply"),
                   "ply\nformat ascii 1.0\ncomment made by hand\nelement vertex 4\nproperty float x\n"
                   "property float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
                   "property uchar red\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                   "0 0 0 0 0 1 10\n1 0 0 0 0 1 20\n0 2 0 0 0 1 30\n1 2 3 0 0 2 40\n3 0 1 2\n");
  const CliRun r = run({"info", path("box.ply")});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  for (const std::string& line :
       {path("box.ply") + "\n", std::string("  format       ply ascii\n"), std::string("  comment      made by hand\n"),
        std::string("  element      vertex 4: x(float) y(float) z(float) nx(float) ny(float) nz(float) red(uchar)\n"),
        std::string("  element      face 1: vertex_indices(list uchar int)\n"), std::string("  points       4\n"),
        std::string("  bounds       [0 0 0] .. [1 2 3]\n"), std::string("  mean radius  "),
        std::string("  normals      yes, 1 not unit length")}) {
    EXPECT_TRUE(contains(r.out, line)) << "no '" << line << "' in\n" << r.out;
  }

  write_whole_file(path("bare.xyz"), "0 0 0\n1 0 0\n0 1 0\n1 1 0\n0.5 0.5 0\n");
  const CliRun text = run({"info", path("bare.xyz")});
  ASSERT_EQ(text.exit_code, 0) << text.describe();
  EXPECT_TRUE(contains(text.out, "format       text (x y z per line)")) << text.out;
  EXPECT_TRUE(contains(text.out, "points       5")) << text.out;
  EXPECT_TRUE(contains(text.out, "normals      none (run pnf estimate)")) << text.out;
}

// The demo on the device when there is one (it is what a user runs first), else the reference.
TEST_F(CliTest, DemoReportsAnImprovement) {
  const SameBackend backend = same_backend();
  const std::string folder = path("demo");
  const CliRun r = run({"demo", "--points", "2000", "--dir", folder, "--backend", backend.flag});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  std::smatch m;
  ASSERT_TRUE(
      std::regex_search(r.out, m, std::regex(R"(improved +([0-9.]+)% of points; mean error ([0-9.]+)x smaller)")))
      << r.out;
  EXPECT_GT(std::stod(m[1]), 50.0) << r.out;
  EXPECT_GT(std::stod(m[2]), 1.0) << r.out;
  EXPECT_EQ(read_point_file(folder + "/house_noisy.ply").size(),
            read_point_file(folder + "/house_filtered.ply").size());
}

TEST_F(CliTest, HelpForEachCommand) {
  const CliRun top = run({"--help"});
  EXPECT_EQ(top.exit_code, 0) << top.describe();
  for (const char* piece : {"filter", "estimate", "info", "devices", "demo", "Exit codes", "PNF_DEVICE"}) {
    EXPECT_TRUE(contains(top.out, piece)) << "no '" << piece << "' in\n" << top.out;
  }
  const std::vector<std::pair<std::string, std::vector<std::string>>> commands = {
      {"filter",
       {"IN", "OUT", "--sigma-f", "--sigma-g", "--iterations", "--units", "--radius", "--device", "--backend",
        "--ascii", "--quiet", "--in-place"}},
      {"estimate", {"IN", "OUT", "--k", "--orient", "--viewpoint", "--in-place"}},
      {"info", {"IN"}},
      {"devices", {"--device"}},
      {"demo", {"--points", "--dir", "--device", "--backend"}}};
  for (const auto& [command, flags] : commands) {
    const CliRun r = run({command, "--help"});
    EXPECT_EQ(r.exit_code, 0) << command << " --help\n" << r.describe();
    for (const std::string& flag : flags) {
      EXPECT_TRUE(contains(r.out, flag)) << "pnf " << command << " --help does not show " << flag << "\n" << r.out;
    }
  }
}

TEST_F(CliTest, FilterHelpShowsTheLibrarysDefaults) {
  // The help's defaults come from the library's structs; a number restated in the CLI drifts
  // (--memory-budget once said 1024 MiB while the library used 3 GiB).
  const CliRun r = run({"filter", "--help"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const FilterParams params;
  const MemoryPolicy memory;
  auto shows = [&](const std::string& flag, const std::string& value) {
    const std::regex pattern(flag + R"( [A-Z:{},a-z]*=)" + value + R"((\s|$))");
    EXPECT_TRUE(std::regex_search(r.out, pattern)) << "pnf filter --help: no " << flag << " default " << value << "\n"
                                                    << r.out;
  };
  auto number = [](double v) {
    std::ostringstream text;
    text << v;
    return text.str();
  };
  shows("--sigma-f", number(params.sigma_f));
  shows("--sigma-g", number(params.sigma_g));
  shows("--iterations", std::to_string(params.iterations));
  shows("--memory-budget", number(double(memory.budget_bytes) / (1024.0 * 1024.0)));
  shows("--max-pairs", std::to_string(memory.max_neighbour_pairs));
  EXPECT_FALSE(contains(r.out, "(default 1024)")) << r.out;
}

TEST_F(CliTest, DeviceFlagTakesTheDeviceValueForms) {
  const std::string in = write_cloud("plane.ply", jittered_grid(20, 1.0, 0.1, 3));
  const CliRun r = run({"filter", in, path("out.ply"), "--device", "reference"});
  EXPECT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_TRUE(contains(r.err, "[reference]")) << r.err;
  const CliRun bad = run({"filter", in, path("bad.ply"), "--device", "opencl:"});
  EXPECT_EQ(bad.exit_code, 2) << bad.describe();
  EXPECT_TRUE(contains(bad.err, "no selector after 'opencl:'")) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(path("bad.ply")));
}

}  // namespace
}  // namespace pnf::test
