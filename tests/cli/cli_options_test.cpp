// The pnf tool's options that Python takes too, read by the same library code: --backend and
// --device (pnf::parse_backend_and_device), --units (pnf::parse_units), --radius (> 0, as
// mean_radius=), the defaults --help and the demo show (pnf::FilterParams{}); and a first run on
// PoCL that prints no compiler warnings. Runs the built binary (PNF_CLI_PATH); skipped when it
// was not built.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "cli_test_support.hpp"
#include "pnf/device.hpp"
#include "pnf/error.hpp"
#include "pnf/filter_params.hpp"
#include "pnf/normal_filter.hpp"
#include "pnf/options_text.hpp"
#include "test_clouds.hpp"

namespace pnf::test {
namespace {

// The library's message for a backend and device pair it refuses.
std::string refusal(const std::string& backend, const std::string& device) {
  try {
    (void)parse_backend_and_device(backend, device);
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "parse_backend_and_device('" << backend << "', '" << device << "') took the pair";
  return "";
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
  shows("--units", to_string(params.units));
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

// --backend reference beside an OpenCL --device was once run on the reference with the device
// silently dropped, while Python refused the same pair: both now go through the library's
// parser and refuse it with its message, naming both, before anything is read or written.
TEST_F(CliTest, ReferenceBackendBesideAnOpenClDeviceIsRefused) {
  const std::string in = write_cloud("plane.ply", jittered_grid(20, 1.0, 0.1, 3));
  for (const std::string device : {"gpu", "pocl", "opencl:cpu", "0:0"}) {
    const CliRun r = run({"filter", in, path("out.ply"), "--backend", "reference", "--device", device});
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_TRUE(contains(r.err, "--backend/--device: " + refusal("reference", device))) << r.err;
    EXPECT_TRUE(contains(r.err, "'" + device + "'")) << r.err;
    EXPECT_FALSE(std::filesystem::exists(path("out.ply")));
  }
  const CliRun demo =
      run({"demo", "--points", "200", "--dir", path("demo"), "--backend", "reference", "--device", "gpu"});
  EXPECT_EQ(demo.exit_code, 2) << demo.describe();
  EXPECT_TRUE(contains(demo.err, refusal("reference", "gpu"))) << demo.err;
  EXPECT_FALSE(std::filesystem::exists(path("demo")));
  // The pairs that agree still run.
  const CliRun same = run({"filter", in, path("same.ply"), "--backend", "reference", "--device", "Reference"});
  EXPECT_EQ(same.exit_code, 0) << same.describe();
  EXPECT_TRUE(contains(same.err, "[reference]")) << same.err;
}

// --radius 0 once meant "estimate it" while Python refused mean_radius=0 and the README calls
// values <= 0 an error: now an error naming the flag (leaving the flag out estimates it).
TEST_F(CliTest, RadiusMustBeFiniteAndPositive) {
  const std::string in = write_cloud("plane.ply", jittered_grid(20, 1.0, 0.1, 3));
  for (const std::string value : {"0", "-0.5", "nan", "inf"}) {
    const CliRun r = run({"filter", in, path("out.ply"), "--backend", "reference", "--radius", value});
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_TRUE(contains(r.err, "--radius: must be finite and > 0, got " + value)) << r.err;
    EXPECT_FALSE(std::filesystem::exists(path("out.ply")));
  }
  // The other numeric flags' bounds, in the same words (CLI11's own range checks printed their
  // upper bound, DBL_MAX, in 300 digits).
  for (const std::vector<std::string>& flag :
       {std::vector<std::string>{"--stop-change", "-1", "must be finite and >= 0, got -1"},
        std::vector<std::string>{"--max-seconds", "-1", "must be finite and >= 0, got -1"},
        std::vector<std::string>{"--memory-budget", "0", "must be finite and > 0, got 0"},
        std::vector<std::string>{"--max-pairs", "0", "must be finite and > 0, got 0"}}) {
    const CliRun r = run({"filter", in, path("out.ply"), "--backend", "reference", flag[0], flag[1]});
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_TRUE(contains(r.err, flag[0] + ": " + flag[2])) << r.err;
    EXPECT_LT(r.err.size(), 200u) << r.err;
  }
  const CliRun given = run({"filter", in, path("given.ply"), "--backend", "reference", "--radius", "0.05"});
  EXPECT_EQ(given.exit_code, 0) << given.describe();
  EXPECT_TRUE(contains(given.err, "mean radius  0.05 (given)")) << given.err;
  const CliRun left_out = run({"filter", in, path("estimated.ply"), "--backend", "reference"});
  EXPECT_EQ(left_out.exit_code, 0) << left_out.describe();
  EXPECT_TRUE(contains(left_out.err, "(estimated")) << left_out.err;
}

// The demo's settings line is printed from pnf::FilterParams{}, the values it runs with.
TEST_F(CliTest, DemoPrintsTheLibrarysDefaults) {
  const CliRun r = run({"demo", "--points", "500", "--dir", path("demo"), "--backend", "reference"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const FilterParams params;
  char expected[128];
  std::snprintf(expected, sizeof expected, "paper defaults: sigma_f %g, sigma_g %g mean radii", params.sigma_f,
                params.sigma_g);
  EXPECT_TRUE(contains(r.out, expected)) << r.out;
  EXPECT_TRUE(contains(r.out, "model units), " + std::to_string(params.iterations) + " passes\n")) << r.out;
}

// The first build of the kernels on PoCL (a fresh kernel cache, as on a new machine) prints
// nothing of the compiler's: no warnings, no "N warnings generated." (clang writes that line to
// stderr itself, outside the build log). The build log is shown only when a build fails.
TEST_F(CliTest, FirstKernelBuildOnPoclPrintsNoCompilerOutput) {
  bool have_pocl = false;
  for (const DeviceInfo& d : list_devices()) {
    have_pocl = have_pocl || contains(d.platform_name, "Portable Computing Language");
  }
  if (!have_pocl) {
    const char* wanted = std::getenv("PNF_DEVICE");
    if (wanted && contains(wanted, "pocl")) FAIL() << "PNF_DEVICE=" << wanted << " but PoCL is not found";
    GTEST_SKIP() << "no PoCL device";
  }
  const std::string in = write_cloud("plane.ply", jittered_grid(20, 1.0, 0.1, 3));
  const std::string cache = (root_ / "pocl_cache").string();
  std::filesystem::create_directory(cache);
  const CliRun r = run({"filter", in, path("out.ply"), "--device", "pocl"}, "POCL_CACHE_DIR=" + shell_quote(cache));
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_FALSE(std::filesystem::is_empty(cache)) << "PoCL did not use the fresh cache, so nothing was compiled";
  for (const char* piece : {"warning", "generated", "error:"}) {
    EXPECT_FALSE(contains(r.err, piece)) << r.err;
  }
  EXPECT_TRUE(contains(r.err, "Portable Computing Language")) << r.err;
}

}  // namespace
}  // namespace pnf::test
