// pnf::read_point_file / write_point_file on the text formats (.xyz, .xyzn, .pwn): comments and
// blank lines, exact doubles, conversion to and from PLY, a leading point count.
#include "pnf/point_file.hpp"
#include "pnf/point_file_header.hpp"

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

TEST(TextFormats, XyzWithoutNormals) {
  TempDir dir;
  test::write_file(dir / "in.xyz", "# a comment\n\n1 2 3\n  -4.5e-3\t5 6\n\n# end\n");
  PointFile file = read_point_file((dir / "in.xyz").string());
  EXPECT_EQ(file.source_format(), PointFileFormat::xyz);
  EXPECT_FALSE(file.has_normals());
  const PointCloud cloud = file.cloud();
  ASSERT_EQ(cloud.size(), 2u);
  EXPECT_FALSE(cloud.has_normals());
  EXPECT_EQ(cloud.positions[1], (Vec3{-4.5e-3, 5, 6}));

  write_point_file((dir / "out.xyz").string(), file);
  EXPECT_EQ(test::read_file(dir / "out.xyz"), "1 2 3\n-0.0044999999999999997 5 6\n");
  EXPECT_THROW(write_point_file((dir / "out.pwn").string(), file), Error);
  EXPECT_FALSE(std::filesystem::exists(dir / "out.pwn"));

  // Normals added to a text file are double, like its positions.
  file.set_normals({{0, 0, 1}, {0.1, 0.2, 0.3}});
  write_point_file((dir / "normals.xyz").string(), file);
  EXPECT_EQ(test::read_file(dir / "normals.xyz"),
            "1 2 3 0 0 1\n-0.0044999999999999997 5 6 0.10000000000000001 0.20000000000000001 "
            "0.29999999999999999\n");
  EXPECT_EQ(read_point_file((dir / "normals.xyz").string()).cloud().normals[1], (Vec3{0.1, 0.2, 0.3}));
}

TEST(TextFormats, EveryTextFormatRoundTripsDoublesExactly) {
  TempDir dir;
  std::mt19937_64 random(42);
  std::uniform_real_distribution<double> coordinate(-1e3, 1e3);
  PointCloud cloud;
  for (int i = 0; i < 200; ++i) {
    cloud.positions.push_back({coordinate(random), coordinate(random) * 1e-200, coordinate(random) * 1e200});
    cloud.normals.push_back({coordinate(random), coordinate(random), coordinate(random)});
  }
  for (const char* name : {"points.xyz", "points.xyzn", "points.pwn", "points.ply"}) {
    write_point_file((dir / name).string(), PointFile(cloud));
    const PointCloud back = read_point_file((dir / name).string()).cloud();
    EXPECT_EQ(back.positions, cloud.positions) << name;
    EXPECT_EQ(back.normals, cloud.normals) << name;
  }
}

TEST(TextFormats, ConvertBetweenTextAndPly) {
  TempDir dir;
  test::write_file(dir / "in.xyzn", "1 2 3 0 0 1\n4 5 6 1 0 0\n");
  const PointFile text = read_point_file((dir / "in.xyzn").string());
  EXPECT_TRUE(text.has_normals());
  for (const bool ascii : {false, true}) {
    write_point_file((dir / "mid.ply").string(), text, WriteOptions{ascii});
    const PointFile ply = read_point_file((dir / "mid.ply").string());
    EXPECT_EQ(ply.header().elements.at(0).properties.at(0).type, PlyScalar::float64);
    EXPECT_EQ(ply.cloud().positions, text.cloud().positions);
    EXPECT_EQ(ply.cloud().normals, text.cloud().normals);
    write_point_file((dir / "back.xyz").string(), ply);
    EXPECT_EQ(test::read_file(dir / "back.xyz"), "1 2 3 0 0 1\n4 5 6 1 0 0\n");
  }

  // PLY to text keeps x y z and normals; float values convert exactly.
  test::write_file(dir / "f.ply",
                   "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                   "property float z\nproperty uchar red\nend_header\n0.1 2 3 255\n");
  write_point_file((dir / "f.xyz").string(), read_point_file((dir / "f.ply").string()));
  EXPECT_EQ(read_point_file((dir / "f.xyz").string()).cloud().positions[0][0], 0.1f);
}

TEST(TextFormats, SkipsAPointCountLine) {
  TempDir dir;
  test::write_file(dir / "counted.pwn", "2\n1 2 3 0 0 1\n4 5 6 1 0 0\n");
  EXPECT_EQ(read_point_file((dir / "counted.pwn").string()).size(), 2u);
}

}  // namespace
}  // namespace pnf
