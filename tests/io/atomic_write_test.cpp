// write_point_file's atomic replacement: the target replaced, no temporary left, nothing left
// behind by a failure.
#include "pnf/point_file.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
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

// A rename over a symbolic link would replace the link and leave the file it leads to as it
// was; the write goes through the link instead, as a shell's `>` does (a relative link, a chain
// of two, and a link to a file not there yet).
TEST(AtomicWrite, WritesThroughSymbolicLinks) {
  TempDir dir;
  const PointFile file(PointCloud{{{1, 2, 3}}, {}, {}});
  test::write_file(dir / "real.xyz", "old contents\n");
  std::filesystem::create_directory(dir / "sub");
  std::filesystem::create_symlink("../real.xyz", dir / "sub" / "link.xyz");
  std::filesystem::create_symlink("sub/link.xyz", dir / "chain.xyz");
  write_point_file((dir / "chain.xyz").string(), file);
  EXPECT_EQ(test::read_file(dir / "real.xyz"), "1 2 3\n");
  EXPECT_TRUE(std::filesystem::is_symlink(dir / "chain.xyz"));
  EXPECT_TRUE(std::filesystem::is_symlink(dir / "sub" / "link.xyz"));
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"chain.xyz", "real.xyz", "sub"}));

  std::filesystem::create_symlink("later.xyz", dir / "dangling.xyz");
  write_point_file((dir / "dangling.xyz").string(), file);
  EXPECT_EQ(test::read_file(dir / "later.xyz"), "1 2 3\n");
  EXPECT_TRUE(std::filesystem::is_symlink(dir / "dangling.xyz"));
}

// A new file made in place of the old one would get 0666 less the umask: a replaced file keeps
// its own permission bits instead, while a new one gets the umask's.
TEST(AtomicWrite, KeepsThePermissionsOfTheFileItReplaces) {
  TempDir dir;
  const PointFile file(PointCloud{{{1, 2, 3}}, {}, {}});
  auto mode_of = [](const std::filesystem::path& p) {
    struct stat status {};
    EXPECT_EQ(::stat(p.c_str(), &status), 0) << p;
    return status.st_mode & 07777;
  };
  for (mode_t mode : {mode_t(0600), mode_t(0640), mode_t(0754)}) {
    test::write_file(dir / "scan.xyz", "old\n");
    ASSERT_EQ(::chmod((dir / "scan.xyz").c_str(), mode), 0);
    write_point_file((dir / "scan.xyz").string(), file);
    EXPECT_EQ(mode_of(dir / "scan.xyz"), mode);
    EXPECT_EQ(test::read_file(dir / "scan.xyz"), "1 2 3\n");
  }
  const mode_t mask = ::umask(0);
  ::umask(mask);
  write_point_file((dir / "new.xyz").string(), file);
  EXPECT_EQ(mode_of(dir / "new.xyz"), 0666 & ~mask);
}

// A link to something that is not a regular file (here /dev/null) is refused, before anything
// is written, where a rename would have replaced the device with a file.
TEST(AtomicWrite, RefusesATargetThatIsNotARegularFile) {
  TempDir dir;
  std::filesystem::create_symlink("/dev/null", dir / "null.xyz");
  try {
    write_point_file((dir / "null.xyz").string(), PointFile(PointCloud{{{1, 2, 3}}, {}, {}}));
    FAIL() << "expected an error";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::io);
    EXPECT_NE(std::string(error.what()).find("null.xyz"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("'/dev/null', where it leads, is not a regular file"), std::string::npos)
        << error.what();
  }
  EXPECT_TRUE(std::filesystem::is_character_file("/dev/null"));
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"null.xyz"});
}

}  // namespace
}  // namespace pnf
