// The failures of the pnf tool: each bad input, bad command line and unwritable output gives one
// "pnf: error: ..." line on stderr that names the file and the place (line, element row or
// vertex), the documented exit code, and leaves nothing behind: no output, no temporary file, the
// input as it was. The filter runs on the reference backend here; the device is not the point.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "cli_test_support.hpp"
#include "pnf/point_file.hpp"
#include "test_clouds.hpp"

namespace pnf::test {
namespace {

// Exit codes, as `pnf --help` documents them.
constexpr int kExitUsage = 2;
constexpr int kExitInput = 3;
constexpr int kExitDevice = 4;
constexpr int kExitOutput = 5;

// Four points of the z = 0 plane with +z normals: valid rows for the files below.
const std::vector<std::string> kGoodRows = {"0 0 0 0 0 1", "1 0 0 0 0 1", "0 1 0 0 0 1", "1 1 0 0 0 1"};
const std::vector<std::string> kPositionsAndNormals = {"x", "y", "z", "nx", "ny", "nz"};

// An ascii PLY whose vertex element declares `declared` rows of float `properties` and holds
// `rows`. Its header has 4 + properties.size() lines, so row i is on line 5 + properties + i.
std::string ascii_ply(const std::vector<std::string>& properties, std::size_t declared,
                      const std::vector<std::string>& rows) {
  std::string text = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(declared) + "\n";
  for (const std::string& p : properties) text += "property float " + p + "\n";
  text += "end_header\n";
  for (const std::string& row : rows) text += row + "\n";
  return text;
}

// The good rows with row `index` replaced by `row`.
std::vector<std::string> rows_with(std::size_t index, const std::string& row) {
  std::vector<std::string> rows = kGoodRows;
  rows[index] = row;
  return rows;
}

class CliErrorTest : public CliTest {
 protected:
  // Runs `args`, expecting exit `code` and one error line that holds every one of `pieces`; the
  // work folder must hold the same files after the run as before (no output, no temporary
  // file), and every file in it the same bytes.
  void expect_clean_failure(const std::vector<std::string>& args, int code, const std::vector<std::string>& pieces) {
    const std::set<std::string> before = folder_entries(work_);
    std::vector<std::string> contents_before;
    for (const std::string& name : before) {
      contents_before.push_back(std::filesystem::is_regular_file(work_ / name) ? read_whole_file(work_ / name) : "");
    }
    const CliRun r = run(args);
    EXPECT_EQ(r.exit_code, code) << r.describe();
    EXPECT_EQ(r.err.rfind("pnf: error: ", 0), 0u) << r.describe();
    EXPECT_EQ(count_lines(r.err), 1u) << "expected one error line\n" << r.describe();
    for (const std::string& piece : pieces)
      EXPECT_TRUE(contains(r.err, piece)) << "no '" << piece << "' in\n" << r.describe();
    EXPECT_EQ(folder_entries(work_), before) << "the failed run left or removed a file\n" << r.describe();
    std::size_t i = 0;
    for (const std::string& name : before) {
      if (std::filesystem::is_regular_file(work_ / name)) {
        EXPECT_EQ(read_whole_file(work_ / name), contents_before[i]) << name << " changed\n" << r.describe();
      }
      ++i;
    }
  }

  // `pnf filter IN OUT --backend reference` on a file holding `contents`.
  void expect_filter_rejects(const std::string& name, const std::string& contents,
                             const std::vector<std::string>& pieces) {
    write_whole_file(path(name), contents);
    std::vector<std::string> all_pieces = {path(name)};
    all_pieces.insert(all_pieces.end(), pieces.begin(), pieces.end());
    expect_clean_failure({"filter", path(name), path("out.ply"), "--backend", "reference"}, kExitInput, all_pieces);
  }
};

// ---- input errors: exit 3, the file and the place named -------------------------------------

TEST_F(CliErrorTest, MissingInputFile) {
  expect_clean_failure({"filter", path("absent.ply"), path("out.ply"), "--backend", "reference"}, kExitInput,
                       {path("absent.ply"), "No such file"});
}

TEST_F(CliErrorTest, InputThatIsAFolder) {
  std::filesystem::create_directory(path("folder.ply"));
  expect_clean_failure({"filter", path("folder.ply"), path("out.ply"), "--backend", "reference"}, kExitInput,
                       {path("folder.ply"), "directory"});
}

// Permissions do not stop root, so this case only runs for other users.
TEST_F(CliErrorTest, UnreadableInputFile) {
  if (::geteuid() == 0) GTEST_SKIP() << "running as root: file permissions do not stop reading";
  const std::string in = write_cloud("locked.ply", jittered_grid(5, 1.0, 0.2, 1));
  std::filesystem::permissions(in, std::filesystem::perms::none);
  expect_clean_failure({"filter", in, path("out.ply"), "--backend", "reference"}, kExitInput,
                       {in, "Permission denied"});
  std::filesystem::permissions(in, std::filesystem::perms::owner_all);
}

// A failed run leaves an existing output as it was.
TEST_F(CliErrorTest, ExistingOutputKept) {
  write_whole_file(path("out.ply"), "the previous result");
  write_whole_file(path("zero.ply"), ascii_ply(kPositionsAndNormals, 4, rows_with(2, "0 1 0 0 0 0")));
  expect_clean_failure({"filter", path("zero.ply"), path("out.ply"), "--backend", "reference"}, kExitInput,
                       {path("zero.ply"), "vertex 2"});
  const std::string in = write_cloud("in.ply", jittered_grid(5, 1.0, 0.2, 1));
  expect_clean_failure({"filter", in, path("out.ply"), "--device", "no-such-device-xyzzy"}, kExitDevice,
                       {"no-such-device-xyzzy"});
}

TEST_F(CliErrorTest, EmptyFile) { expect_filter_rejects("empty.ply", "", {"empty"}); }

TEST_F(CliErrorTest, NotAPlyFile) { expect_filter_rejects("text.ply", "hello\nworld\n", {"not a PLY file"}); }

TEST_F(CliErrorTest, HeaderWithoutEnd) {
  expect_filter_rejects("no_end.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", {"end_header"});
}

// The header declares 6 vertices; the body ends after 4 (lines 11 to 14).
TEST_F(CliErrorTest, AsciiHeaderDeclaresMoreRowsThanTheFileHolds) {
  expect_filter_rejects("short.ply", ascii_ply(kPositionsAndNormals, 6, kGoodRows), {"vertex", "4", "ends"});
}

// A binary file cut 10 bytes short: the last of its 100 rows (48 bytes each) is incomplete.
TEST_F(CliErrorTest, TruncatedBinaryFile) {
  const std::string file = write_cloud("cut.ply", jittered_grid(10, 1.0, 0.2, 1));
  std::filesystem::resize_file(file, std::filesystem::file_size(file) - 10);
  expect_clean_failure({"filter", file, path("out.ply"), "--backend", "reference"}, kExitInput,
                       {file, "'vertex'", "row 99", "ends"});
}

TEST_F(CliErrorTest, MalformedNumber) {
  expect_filter_rejects("word.ply", ascii_ply(kPositionsAndNormals, 4, rows_with(2, "0 1 zero 0 0 1")),
                        {"line 13", "'vertex'", "zero"});
}

TEST_F(CliErrorTest, RowWithTooFewValues) {
  expect_filter_rejects("few.ply", ascii_ply(kPositionsAndNormals, 4, rows_with(1, "1 0 0 0 0")),
                        {"line 12", "'vertex'"});
}

TEST_F(CliErrorTest, MissingCoordinateProperty) {
  expect_filter_rejects("no_z.ply", ascii_ply({"x", "y", "nx", "ny", "nz"}, 1, {"0 0 0 0 1"}), {"vertex", "'z'"});
}

TEST_F(CliErrorTest, MissingNormalsPointsToEstimate) {
  expect_filter_rejects("bare.ply", ascii_ply({"x", "y", "z"}, 3, {"0 0 0", "1 0 0", "0 1 0"}),
                        {"normals", "pnf estimate"});
}

TEST_F(CliErrorTest, NaNCoordinate) {
  expect_filter_rejects("nan.ply", ascii_ply(kPositionsAndNormals, 4, rows_with(1, "nan 0 0 0 0 1")),
                        {"line 12", "vertex 1", "x", "NaN"});
}

// A partly NaN normal on a valid point: `filter` refuses it and points to `estimate`, which
// replaces every normal and so takes the file; `info` counts it. (A normal NaN in all three
// components, as PCL's NormalEstimation leaves one, is a point without a normal that `filter`
// keeps as it was: CliTest.FilterKeepsPointsWithoutNormalsAsTheyWere.)
TEST_F(CliErrorTest, NaNNormalPointsToEstimateWhichTakesIt) {
  expect_filter_rejects("nan_normal.ply", ascii_ply(kPositionsAndNormals, 4, rows_with(2, "0 1 0 nan 0 1")),
                        {"line 13", "vertex 2", "nx", "NaN", "pnf estimate"});
  const CliRun info = run({"info", path("nan_normal.ply")});
  ASSERT_EQ(info.exit_code, 0) << info.describe();
  EXPECT_TRUE(contains(info.out, "1 NaN, infinite or zero")) << info.describe();
  const CliRun r = run({"estimate", path("nan_normal.ply"), path("estimated.ply"), "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const PointCloud cloud = read_point_file(path("estimated.ply")).cloud();
  ASSERT_EQ(cloud.normals.size(), 4u);
  for (const Vec3& n : cloud.normals) EXPECT_NEAR(std::abs(n[2]), 1.0, 1e-9) << "a plane's normal";
}

TEST_F(CliErrorTest, InfiniteNormal) {
  expect_filter_rejects("inf.ply", ascii_ply(kPositionsAndNormals, 4, rows_with(3, "1 1 0 0 inf 1")),
                        {"line 14", "vertex 3", "ny", "infinity"});
}

TEST_F(CliErrorTest, ZeroNormal) {
  expect_filter_rejects("zero.ply", ascii_ply(kPositionsAndNormals, 4, rows_with(2, "0 1 0 0 0 0")),
                        {"line 13", "vertex 2", "zero"});
}

// A bad radius property is named by the file's row and the file (row 1, without a normal, is
// left out of the points filtered: the index among those, one lower, was named before); a given
// mean radius or absolute units leave the property unread, so it is no error there.
TEST_F(CliErrorTest, BadRadiusPropertyNamesItsRowUnlessItIsNotRead) {
  std::vector<std::string> rows;
  for (int i = 0; i < 36; ++i) {
    const std::string xy = std::to_string(i % 6) + " " + std::to_string(i / 6) + " 0 ";
    rows.push_back(xy + (i == 1 ? "nan nan nan" : "0 0 1") + (i == 20 ? " 0" : " 0.5"));
  }
  const std::string file = ascii_ply({"x", "y", "z", "nx", "ny", "nz", "radius"}, rows.size(), rows);
  expect_filter_rejects("radius.ply", file, {"vertex 20 has radius 0;", "must be finite and > 0"});
  for (const std::vector<std::string>& flags :
       {std::vector<std::string>{"--radius", "0.5"}, std::vector<std::string>{"--units", "absolute"}}) {
    std::vector<std::string> args = {"filter", path("radius.ply"), path("out.ply"), "--backend", "reference"};
    args.insert(args.end(), flags.begin(), flags.end());
    const CliRun r = run(args);
    EXPECT_EQ(r.exit_code, 0) << r.describe();
    EXPECT_EQ(read_point_file(path("out.ply")).size(), 36u) << flags[0];
    std::filesystem::remove(path("out.ply"));
  }
}

// In a binary file there are no lines: the vertex index is the place.
TEST_F(CliErrorTest, NaNInBinaryFile) {
  const std::string file = write_cloud("nan_binary.ply", jittered_grid(4, 1.0, 0.2, 1));
  std::string bytes = read_whole_file(file);
  const std::size_t body = bytes.find("end_header\n") + std::strlen("end_header\n");
  constexpr std::size_t kRowBytes = 6 * sizeof(double);  // double x y z nx ny nz
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(&bytes[body + 5 * kRowBytes + 2 * sizeof(double)], &nan, sizeof(double));  // vertex 5, z
  write_whole_file(file, bytes);
  expect_clean_failure({"filter", file, path("out.ply"), "--backend", "reference"}, kExitInput,
                       {file, "vertex 5", "z", "NaN"});
}

TEST_F(CliErrorTest, TextFileWithAShortLine) {
  expect_filter_rejects("short_line.xyz", "0 0 0 0 0 1\n1 0 0 0 0\n0 1 0 0 0 1\n", {"line 2"});
}

TEST_F(CliErrorTest, TextFileWithNaN) {
  expect_filter_rejects("nan.xyz", "0 0 0 0 0 1\n1 0 0 0 0 1\n0 nan 0 0 0 1\n", {"line 3", "NaN"});
}

TEST_F(CliErrorTest, EstimateRejectsNaN) {
  write_whole_file(path("nan.xyz"), "0 0 0\n1 0 0\nnan 1 0\n1 1 0\n");
  expect_clean_failure({"estimate", path("nan.xyz"), path("out.ply")}, kExitInput, {path("nan.xyz"), "line 3", "NaN"});
}

TEST_F(CliErrorTest, EstimateNeedsThreePoints) {
  write_whole_file(path("two.xyz"), "0 0 0\n1 0 0\n");
  expect_clean_failure({"estimate", path("two.xyz"), path("out.ply")}, kExitInput, {"3"});
}

// A malformed value stops `info`; a bad normal is counted instead (info describes the file).
TEST_F(CliErrorTest, InfoOnMalformedFile) {
  write_whole_file(path("word.ply"), ascii_ply(kPositionsAndNormals, 4, rows_with(2, "0 1 zero 0 0 1")));
  expect_clean_failure({"info", path("word.ply")}, kExitInput, {path("word.ply"), "line 13", "row 2", "zero"});
  write_whole_file(path("zero.ply"), ascii_ply(kPositionsAndNormals, 4, rows_with(2, "0 1 0 0 0 0")));
  const CliRun r = run({"info", path("zero.ply")});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_TRUE(contains(r.out, "1 NaN, infinite or zero")) << r.describe();
}

// --pcd-data for an OUT that is not .pcd is a usage error before any work (it was ignored);
// the same for estimate.
TEST_F(CliErrorTest, PcdDataForAnOutputThatIsNotPcd) {
  const std::string in = write_cloud("in.ply", jittered_grid(5, 1.0, 0.2, 1));
  for (const std::string command : {"filter", "estimate"}) {
    expect_clean_failure({command, in, path("out.ply"), "--pcd-data", "binary"}, 2,
                         {path("out.ply"), "a PCD DATA encoding (--pcd-data binary)", "not .pcd"});
  }
}

// ---- output errors: exit 5, nothing created ---------------------------------------------------

TEST_F(CliErrorTest, OutputInAMissingFolder) {
  const std::string in = write_cloud("in.ply", jittered_grid(5, 1.0, 0.2, 1));
  const std::string out = path("no_such_folder/out.ply");
  expect_clean_failure({"filter", in, out, "--backend", "reference"}, kExitOutput, {out});
}

// A folder at OUT is refused before anything is written (once the rename failed after the
// write, and the temporary file had to go too).
TEST_F(CliErrorTest, OutputThatIsAFolder) {
  const std::string in = write_cloud("in.ply", jittered_grid(5, 1.0, 0.2, 1));
  std::filesystem::create_directory(path("out.ply"));
  expect_clean_failure({"filter", in, path("out.ply"), "--backend", "reference"}, kExitOutput, {path("out.ply")});
  EXPECT_TRUE(std::filesystem::is_empty(path("out.ply")));
}

TEST_F(CliErrorTest, EstimateOutputInAMissingFolder) {
  write_whole_file(path("in.xyz"), "0 0 0\n1 0 0\n0 1 0\n1 1 0\n");
  const std::string out = path("no_such_folder/out.ply");
  expect_clean_failure({"estimate", path("in.xyz"), out}, kExitOutput, {out});
}

TEST_F(CliErrorTest, DemoIntoAFile) {
  write_whole_file(path("not_a_folder"), "x");
  expect_clean_failure({"demo", "--points", "200", "--dir", path("not_a_folder"), "--backend", "reference"},
                       kExitOutput, {path("not_a_folder")});
}

// The demo writes nothing, not even its folder, when the device is not there.
TEST_F(CliErrorTest, DemoWithoutItsDevice) {
  expect_clean_failure({"demo", "--points", "200", "--dir", path("demo"), "--device", "no-such-device-xyzzy"},
                       kExitDevice, {"no-such-device-xyzzy"});
}

// ---- usage errors: exit 2, before any work ----------------------------------------------------

TEST_F(CliErrorTest, UnknownOutputExtension) {
  const std::string in = write_cloud("in.ply", jittered_grid(5, 1.0, 0.2, 1));
  expect_clean_failure({"filter", in, path("out.txt"), "--backend", "reference"}, kExitUsage,
                       {path("out.txt"), ".txt"});
}

TEST_F(CliErrorTest, BadParameterValues) {
  const std::string in = write_cloud("in.ply", jittered_grid(5, 1.0, 0.2, 1));
  expect_clean_failure({"filter", in, path("out.ply"), "--sigma-f", "-1"}, kExitUsage, {"sigma_f", "-1"});
  expect_clean_failure({"filter", in, path("out.ply"), "--iterations", "-2"}, kExitUsage, {"iterations", "-2"});
  expect_clean_failure({"estimate", in, path("out.ply"), "--k", "2"}, kExitUsage, {"k", "2"});
  // --radius <= 0 is refused by its flag's check, before anything runs: cli_options_test.cpp.
}

TEST_F(CliErrorTest, OutputIsInputWithoutInPlace) {
  const std::string in = write_cloud("in.ply", jittered_grid(5, 1.0, 0.2, 1));
  expect_clean_failure({"filter", in, in, "--backend", "reference"}, kExitUsage, {in, "--in-place"});
  // The same file under another spelling.
  const std::string other = (work_ / "." / "in.ply").string();
  expect_clean_failure({"filter", in, other, "--backend", "reference"}, kExitUsage, {"--in-place"});
  expect_clean_failure({"estimate", in, in}, kExitUsage, {in, "--in-place"});
}

// CLI11 reports these itself (with a hint to use --help); only the exit code and that nothing was
// written are ours to check.
TEST_F(CliErrorTest, UnknownFlagsAndCommands) {
  const std::string in = write_cloud("in.ply", jittered_grid(5, 1.0, 0.2, 1));
  const std::set<std::string> before = folder_entries(work_);
  for (const std::vector<std::string>& args :
       std::vector<std::vector<std::string>>{{"filter", in, path("out.ply"), "--frobnicate"},
                                             {"filter", in, path("out.ply"), "--units", "furlongs"},
                                             {"filter", in, path("out.ply"), "--backend", "quantum"},
                                             {"filter", in, path("out.ply"), "--memory-budget", "-5"},
                                             {"filter", in, path("out.ply"), "--iterations", "four"},
                                             {"filter", in},
                                             {"estimate", in, path("out.ply"), "--orient", "sideways"},
                                             {"info"},
                                             {"info", in, "--frobnicate"},
                                             {"devices", "--frobnicate"},
                                             {"demo", "--frobnicate"},
                                             {"--frobnicate"},
                                             {"frobnicate"},
                                             {}}) {
    const CliRun r = run(args);
    std::string line;
    for (const std::string& a : args) line += " " + a;
    EXPECT_EQ(r.exit_code, kExitUsage) << "pnf" << line << "\n" << r.describe();
    EXPECT_FALSE(r.err.empty()) << "pnf" << line << " printed no error";
  }
  EXPECT_EQ(folder_entries(work_), before);
}

// A mistyped command is named, with the ones there are (as git does), not "a subcommand is required".
TEST_F(CliErrorTest, MistypedCommandIsNamed) {
  const std::string in = write_cloud("in.ply", jittered_grid(5, 1.0, 0.2, 1));
  const std::set<std::string> before = folder_entries(work_);
  const CliRun r = run({"fliter", in, path("out.ply")});
  EXPECT_EQ(r.exit_code, kExitUsage) << r.describe();
  EXPECT_EQ(folder_entries(work_), before);
  EXPECT_NE(r.err.find("'fliter' is not a pnf command"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("filter, estimate, info"), std::string::npos) << r.err;
}

// ---- device errors: exit 4 --------------------------------------------------------------------

// Whether or not OpenCL is present, a selector that matches nothing is a device error.
TEST_F(CliErrorTest, DeviceThatMatchesNothing) {
  const std::string in = write_cloud("in.ply", jittered_grid(5, 1.0, 0.2, 1));
  expect_clean_failure({"filter", in, path("out.ply"), "--device", "no-such-device-xyzzy"}, kExitDevice,
                       {"no-such-device-xyzzy"});
}

}  // namespace
}  // namespace pnf::test
