// The pnf tool end to end, `filter`: on a real scan against the library run in this process,
// --in-place, each format, points without normals, the summary and progress display, Ctrl-C.
// `estimate`, `devices`, `info`, `demo` and --help are in cli_commands_test.cpp, the options
// shared with Python in cli_options_test.cpp, the failures in cli_errors_test.cpp. Runs the
// built binary (PNF_CLI_PATH); skipped when it was not built.
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

#include "cli_backend.hpp"
#include "cli_test_support.hpp"
#include "pnf/device.hpp"
#include "pnf/normal_filter.hpp"
#include "pnf/point_file.hpp"
#include "pnf/point_file_header.hpp"
#include "pnf/synthetic_shapes.hpp"
#include "test_backends.hpp"
#include "test_clouds.hpp"

namespace pnf::test {
namespace {

// A jittered 20 x 20 grid in z = 0 with normals tilted about 10 degrees from +z.
PointCloud noisy_grid() {
  constexpr double kTiltDegrees = 10;
  PointCloud c = jittered_grid(20, 1.0, 0.2, 7);
  std::mt19937 rng(8);
  for (Vec3& n : c.normals) n = jitter_normal(n, kTiltDegrees, rng);
  return c;
}

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

// No pass run: the summary says none (it printed "passes 0: s"), and no chunks (it printed "in 0
// chunks").
TEST_F(CliTest, NoPassesSaysNone) {
  const std::string in = write_cloud("plane.ply", jittered_grid(20, 1.0, 0.1, 3));
  const CliRun r = run({"filter", in, path("out.ply"), "--backend", "reference", "--iterations", "0"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_TRUE(contains(r.err, "  passes       none\n")) << r.err;
  EXPECT_TRUE(contains(r.err, " pairs per pass\n")) << r.err;
  EXPECT_FALSE(contains(r.err, "chunk")) << r.err;
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
  // The summary says what became of those rows: kept in place here; left out of a text OUT,
  // which cannot hold NaN (it said "kept" there too).
  EXPECT_NE(r.err.find("kept         3 points without normals (NaN) as they were"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("kept         1 invalid points (a NaN coordinate) as they were"), std::string::npos) << r.err;
  const CliRun text_run = run({"filter", path("pcl.pcd"), path("out.xyz"), "--backend", "reference"});
  ASSERT_EQ(text_run.exit_code, 0) << text_run.describe();
  EXPECT_EQ(read_point_file(path("out.xyz")).size(), 396u);
  EXPECT_NE(text_run.err.find("left out     3 points without normals (NaN) (a text file cannot hold NaN)"),
            std::string::npos)
      << text_run.err;
  EXPECT_NE(text_run.err.find("left out     1 invalid points (a NaN coordinate) (a text file cannot hold NaN)"),
            std::string::npos)
      << text_run.err;
  EXPECT_EQ(text_run.err.find("kept "), std::string::npos) << text_run.err;
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

}  // namespace
}  // namespace pnf::test
