// Smoke tests of `pnf render` and `pnf compare` through the built tool (PNF_CLI_PATH; skipped
// when it is empty): the pictures come out at the promised size, and bad arguments and bad
// files give exit codes 2 and 3 with a message that says what is wrong, leaving no file.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "pnf/point_file.hpp"
#include "pnf/render.hpp"
#include "png_header.hpp"
#include "test_clouds.hpp"

#ifndef PNF_CLI_PATH
#define PNF_CLI_PATH ""
#endif

namespace pnf {
namespace {

namespace fs = std::filesystem;

std::string quote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

class RenderCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::string(PNF_CLI_PATH).empty()) GTEST_SKIP() << "the pnf tool is not built: PNF_CLI_PATH is empty";
    std::string pattern = (fs::temp_directory_path() / "pnf_render_cli_XXXXXX").string();
    ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
    root_ = pattern;
    work_ = root_ / "work";
    fs::create_directory(work_);
    const PointCloud sphere = test::sphere(3000, 1.0, 1);
    write_point_file(path("sphere.ply"), PointFile(sphere));
    PointCloud noisy = sphere;
    std::mt19937 rng(2);
    for (Vec3& n : noisy.normals) n = test::jitter_normal(n, 10, rng);
    write_point_file(path("noisy.ply"), PointFile(noisy));
    PointCloud fewer = sphere;
    fewer.positions.pop_back();
    fewer.normals.pop_back();
    write_point_file(path("fewer.ply"), PointFile(fewer));
    PointCloud bare = sphere;
    bare.normals.clear();
    write_point_file(path("bare.ply"), PointFile(bare));
  }
  void TearDown() override {
    std::error_code ignored;
    if (!root_.empty()) fs::remove_all(root_, ignored);
  }

  std::string path(const std::string& name) const { return (work_ / name).string(); }

  // Runs `pnf args...`; returns the exit code (-1 if it did not exit) and keeps stderr in err_.
  int run(const std::vector<std::string>& args) {
    const fs::path err = root_ / "stderr.txt";
    std::string command = quote(PNF_CLI_PATH);
    for (const std::string& arg : args) command += " " + quote(arg);
    command += " </dev/null >/dev/null 2>" + quote(err.string());
    const int status = std::system(command.c_str());
    err_ = render_test::read_bytes(err.string());
    return status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  std::set<std::string> entries() const {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(work_)) names.insert(e.path().filename().string());
    return names;
  }

  fs::path root_, work_;
  std::string err_;
};

TEST_F(RenderCliTest, RenderWritesAPictureOfTheAskedSize) {
  for (const std::vector<std::string>& extra :
       std::vector<std::vector<std::string>>{{},
                                             {"--mode", "normals", "--view", "30,20"},
                                             {"--mode", "error", "--truth", path("noisy.ply")},
                                             {"--light", "1,1,1", "--radius-scale", "1.5", "--view", "-45.5, -10"}}) {
    std::vector<std::string> args = {"render", path("sphere.ply"), path("out.png"), "--width", "200", "--height",
                                     "150"};
    args.insert(args.end(), extra.begin(), extra.end());
    ASSERT_EQ(run(args), 0) << err_;
    const render_test::PngHeader header = render_test::read_png_header(path("out.png"));
    ASSERT_TRUE(header.valid);
    EXPECT_EQ(header.width, 200u);
    EXPECT_EQ(header.height, 150u);
    EXPECT_NE(err_.find("wrote"), std::string::npos) << err_;
  }
  ASSERT_EQ(run({"render", path("sphere.ply"), path("default.png"), "-q"}), 0) << err_;
  EXPECT_EQ(render_test::read_png_header(path("default.png")).width, unsigned(RenderOptions{}.width));
  EXPECT_TRUE(err_.empty()) << err_;
}

TEST_F(RenderCliTest, CompareLaysOutPanelsSideBySide) {
  ASSERT_EQ(
      run({"compare", path("noisy.ply"), path("sphere.ply"), path("cmp.png"), "--width", "200", "--height", "150"}), 0)
      << err_;
  EXPECT_EQ(render_test::read_png_header(path("cmp.png")).width, 400u);
  ASSERT_EQ(run({"compare", path("noisy.ply"), path("sphere.ply"), path("cmp3.png"), "--width", "200", "--height",
                 "150", "--error-panel"}),
            0)
      << err_;
  const render_test::PngHeader header = render_test::read_png_header(path("cmp3.png"));
  // Two panels, then the error panel widened by its colour bar so that its points keep the camera.
  EXPECT_EQ(header.width, unsigned(3 * 200 + RenderOptions{}.colour_bar_width));
  EXPECT_EQ(header.height, 150u);
  EXPECT_NE(err_.find("mean"), std::string::npos) << "the mean angle is reported: " << err_;
}

TEST_F(RenderCliTest, BadArgumentsAndFilesFailWithAClearMessageAndNoFile) {
  struct Case {
    std::vector<std::string> args;
    int exit_code;
    std::string words;  // expected in the message
  };
  const std::string in = path("sphere.ply"), out = path("bad.png");
  const std::vector<Case> cases = {
      {{"render", in, out, "--width", "0"}, 2, "width"},
      {{"render", in, out, "--height", "99999"}, 2, "height"},
      {{"render", in, out, "--view", "30"}, 2, "--view"},
      {{"render", in, out, "--view", "thirty,20"}, 2, "--view"},
      {{"render", in, out, "--view", "0,120"}, 2, "elevation"},
      {{"render", in, out, "--light", "0,0,0"}, 2, "light"},
      {{"render", in, out, "--radius-scale", "-1"}, 2, "radius scale"},
      {{"render", in, out, "--mode", "error"}, 2, "--truth"},
      {{"render", in, out, "--truth", path("noisy.ply")}, 2, "--mode error"},
      {{"render", in, path("bad.jpg")}, 2, ".png"},
      {{"render", in, out, "--mode", "error", "--truth", path("fewer.ply")}, 3, "2999"},
      {{"render", in, out, "--mode", "error", "--truth", path("missing.ply")}, 3, "missing.ply"},
      {{"render", path("bare.ply"), out}, 3, "no normals"},
      {{"render", path("missing.ply"), out}, 3, "missing.ply"},
      {{"compare", in, path("fewer.ply"), out, "--error-panel"}, 3, "2999"},
      {{"compare", in, path("noisy.ply"), out, "--view", "1,2,3"}, 2, "--view"},
  };
  const std::set<std::string> before = entries();
  for (const Case& c : cases) {
    std::string line;
    for (const std::string& a : c.args) line += " " + a;
    EXPECT_EQ(run(c.args), c.exit_code) << line << "\n" << err_;
    EXPECT_NE(err_.find(c.words), std::string::npos) << line << "\nexpected '" << c.words << "' in: " << err_;
    EXPECT_EQ(entries(), before) << line << " left a file behind";
  }
}

}  // namespace
}  // namespace pnf
