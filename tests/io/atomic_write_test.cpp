// write_point_file's atomic replacement: the target replaced, no temporary left, nothing left
// behind by a failure.
#include "pnf/point_file.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "ply_test_files.hpp"
#include "pnf/error.hpp"

namespace pnf {
namespace {

using test::TempDir;

TEST(AtomicWrite, ReplacesTheTargetAndLeavesNoTemporaryFile) {
  TempDir dir;
  test::write_file(dir / "out.xyz", "old contents\n");
  write_point_file((dir / "out.xyz").string(), PointFile(PointCloud{{{1, 2, 3}}, {}, {}}));
  EXPECT_EQ(test::read_file(dir / "out.xyz"), "1 2 3\n");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.xyz"});
}

TEST(AtomicWrite, FailureLeavesNothingBehind) {
  TempDir dir;
  const PointFile file(PointCloud{{{1, 2, 3}}, {}, {}});

  const std::string missing = (dir / "no_such_folder" / "out.ply").string();
  try {
    write_point_file(missing, file);
    FAIL() << "expected an error";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::io);
    EXPECT_NE(std::string(error.what()).find(missing), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("No such file or directory"), std::string::npos) << error.what();
  }

  // The target is a folder: the rename fails after the data was written.
  std::filesystem::create_directory(dir / "folder.ply");
  try {
    write_point_file((dir / "folder.ply").string(), file);
    FAIL() << "expected an error";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::io);
    EXPECT_NE(std::string(error.what()).find("folder.ply"), std::string::npos) << error.what();
  }
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"folder.ply"});

  // A folder without write permission (root ignores permissions, so only as another user).
  if (::geteuid() != 0) {
    std::filesystem::create_directory(dir / "locked");
    std::filesystem::permissions(dir / "locked",
                                 std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
    const std::string locked = (dir / "locked" / "out.ply").string();
    try {
      write_point_file(locked, file);
      ADD_FAILURE() << "expected an error";
    } catch (const Error& error) {
      EXPECT_EQ(error.code(), ErrorCode::io);
      EXPECT_NE(std::string(error.what()).find(locked), std::string::npos) << error.what();
      EXPECT_NE(std::string(error.what()).find("Permission denied"), std::string::npos) << error.what();
    }
    std::filesystem::permissions(dir / "locked", std::filesystem::perms::owner_all);
    EXPECT_TRUE(std::filesystem::is_empty(dir / "locked"));
  }
}

}  // namespace
}  // namespace pnf
