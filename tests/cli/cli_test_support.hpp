// Running the built `pnf` tool from a test: a fresh folder per test, the command line quoted for
// the shell, stdout and stderr captured to files, and the exit code. Shared by cli_test.cpp and
// cli_errors_test.cpp.
#pragma once

#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include "pnf/point_cloud.hpp"
#include "pnf/point_file.hpp"

#ifndef PNF_CLI_PATH
#define PNF_CLI_PATH ""
#endif

namespace pnf::test {

// What one run of the tool left.
struct CliRun {
  int exit_code = -1;  // -1 when it did not exit normally (killed by a signal)
  std::string out;     // stdout
  std::string err;     // stderr

  // For failure messages: the whole run at a glance.
  std::string describe() const {
    return "exit " + std::to_string(exit_code) + "\n--- stdout ---\n" + out + "--- stderr ---\n" + err;
  }
};

// Single quotes for the shell: nothing inside them is expanded.
inline std::string shell_quote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

inline std::string read_whole_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

inline void write_whole_file(const std::filesystem::path& path, const std::string& contents) {
  std::ofstream out(path, std::ios::binary);
  out << contents;
}

// The names in `folder`, hidden ones (a writer's temporary files) included.
inline std::set<std::string> folder_entries(const std::filesystem::path& folder) {
  std::set<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) names.insert(entry.path().filename().string());
  return names;
}

inline bool contains(const std::string& text, const std::string& piece) {
  return text.find(piece) != std::string::npos;
}

inline std::size_t count_lines(const std::string& text) {
  return std::size_t(std::count(text.begin(), text.end(), '\n'));
}

// A test that runs the tool. Each test gets its own folder: `work` for inputs and outputs (so
// that a listing of it shows any file a failed run left behind) and, beside it, the captured
// streams. Skips when the tool was not built.
class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::string(PNF_CLI_PATH).empty()) {
      GTEST_SKIP() << "the pnf tool is not built (configure with PNF_BUILD_TOOLS=ON): PNF_CLI_PATH is empty";
    }
    std::string pattern = (std::filesystem::temp_directory_path() / "pnf_cli_test_XXXXXX").string();
    ASSERT_NE(::mkdtemp(pattern.data()), nullptr) << "cannot make a folder from " << pattern;
    root_ = pattern;
    work_ = root_ / "work";
    std::filesystem::create_directory(work_);
  }

  void TearDown() override {
    std::error_code ignored;
    if (!root_.empty()) std::filesystem::remove_all(root_, ignored);
  }

  // A path in the work folder.
  std::string path(const std::string& name) const { return (work_ / name).string(); }

  // Runs `pnf args...`, stdin from /dev/null. `environment` is put before the command as is
  // (e.g. "env -u PNF_DEVICE").
  CliRun run(const std::vector<std::string>& args, const std::string& environment = "") const {
    const std::filesystem::path out = root_ / "stdout.txt", err = root_ / "stderr.txt";
    std::string command = environment + (environment.empty() ? "" : " ") + shell_quote(PNF_CLI_PATH);
    for (const std::string& arg : args) command += " " + shell_quote(arg);
    command += " </dev/null >" + shell_quote(out.string()) + " 2>" + shell_quote(err.string());
    const int status = std::system(command.c_str());
    CliRun result;
    result.exit_code = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    result.out = read_whole_file(out);
    result.err = read_whole_file(err);
    return result;
  }

  // Writes `cloud` with pnf's writer (binary little endian PLY, or text for .xyz).
  std::string write_cloud(const std::string& name, const PointCloud& cloud) const {
    write_point_file(path(name), PointFile(cloud));
    return path(name);
  }

  std::filesystem::path root_;
  std::filesystem::path work_;
};

}  // namespace pnf::test
