// pnf::PointFile beyond the encodings (point_file_encodings_test.cpp): comments kept in place,
// loose spacing, extensions, scalar properties, PointCloud conversion and copies.
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

TEST(PointFile, KeepsCommentsInTheirPlaces) {
  TempDir dir;
  const std::string header_before =
      "ply\n"
      "comment before format\n"
      "format ascii 1.0\n"
      "obj_info after format\n"
      "element vertex 1\n"
      "property float x\n"
      "comment between properties\n"
      "property float y\n"
      "property float z\n"
      "comment after the vertex properties\n"
      "element face 1\n"
      "comment inside face\n"
      "property list uchar int vertex_indices\n"
      "comment last\n"
      "end_header\n";
  test::write_file(dir / "in.ply", header_before + "1 2 3\n1 0\n");
  PointFile file = read_point_file((dir / "in.ply").string());
  write_point_file((dir / "same.ply").string(), file, WriteOptions{true});
  EXPECT_EQ(test::read_file(dir / "same.ply"), header_before + "1 2 3\n1 0\n");

  // Added normals go after the last vertex property; comments below them move down with the
  // lines they preceded.
  file.set_normals({{0, 0, 1}});
  write_point_file((dir / "normals.ply").string(), file, WriteOptions{true});
  EXPECT_EQ(test::read_file(dir / "normals.ply"),
            "ply\n"
            "comment before format\n"
            "format ascii 1.0\n"
            "obj_info after format\n"
            "element vertex 1\n"
            "property float x\n"
            "comment between properties\n"
            "property float y\n"
            "property float z\n"
            "comment after the vertex properties\n"
            "property float nx\n"
            "property float ny\n"
            "property float nz\n"
            "element face 1\n"
            "comment inside face\n"
            "property list uchar int vertex_indices\n"
            "comment last\n"
            "end_header\n"
            "1 2 3 0 0 1\n"
            "1 0\n");
}

TEST(PointFile, ReadsCrLfLineEndingsAndLooseSpacing) {
  TempDir dir;
  test::write_file(dir / "crlf.ply",
                   "ply\r\nformat ascii 1.0\r\ncomment made on Windows\r\nelement vertex 2\r\n"
                   "property double x\r\nproperty double y\r\nproperty double z\r\n"
                   "end_header\r\n1 2 3\r\n\r\n  4\t5   6  \r\n");
  const PointFile file = read_point_file((dir / "crlf.ply").string());
  EXPECT_EQ(file.header().comments.at(0).text, "made on Windows");
  const PointCloud cloud = file.cloud();
  ASSERT_EQ(cloud.size(), 2u);
  EXPECT_EQ(cloud.positions[1], (Vec3{4, 5, 6}));

  // A binary body after a \r\n header.
  std::string binary =
      "ply\r\nformat binary_little_endian 1.0\r\nelement vertex 1\r\nproperty float x\r\n"
      "property float y\r\nproperty float z\r\nend_header\r\n";
  const float xyz[3] = {1.5f, -2, 3};
  binary.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
  test::write_file(dir / "crlf_binary.ply", binary);
  EXPECT_EQ(read_point_file((dir / "crlf_binary.ply").string()).cloud().positions[0], (Vec3{1.5, -2, 3}));
}

TEST(PointFile, ExtensionIsCaseInsensitive) {
  TempDir dir;
  test::write_file(dir / "upper.PLY",
                   "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                   "property float y\nproperty float z\nend_header\n1 2 3\n");
  test::write_file(dir / "upper.XyZ", "1 2 3\n");
  EXPECT_EQ(read_point_file((dir / "upper.PLY").string()).size(), 1u);
  EXPECT_EQ(read_point_file((dir / "upper.XyZ").string()).size(), 1u);
  write_point_file((dir / "out.PwN").string(), PointFile(PointCloud{{{1, 2, 3}}, {{0, 0, 1}}, {}}));
  EXPECT_EQ(test::read_file(dir / "out.PwN"), "1 2 3 0 0 1\n");
}

// set_scalar_property replaces one float property (pnf estimate's curvature) and nothing else:
// in ascii PLY every other token keeps its text; invalid points get NaN; coordinates, normals,
// integer, absent properties and a wrong count are refused.
TEST(PointFile, SetScalarPropertyReplacesOnlyThatProperty) {
  TempDir dir;
  test::write_file(dir / "in.ply",
                   "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                   "property float z\nproperty float curvature\nproperty int label\nend_header\n"
                   "0 0 0 0.50 +7\nnan nan nan 0.5 8\n1 0 0 0.5 9\n0 1 0 5e-1 10\n");
  PointFile file = read_point_file((dir / "in.ply").string());
  ASSERT_EQ(file.valid_count(), 3u);
  EXPECT_TRUE(file.has_scalar_property("curvature"));
  EXPECT_FALSE(file.has_scalar_property("intensity"));
  file.set_scalar_property("curvature", {0.25, 0, 0.125});
  WriteOptions ascii;
  ascii.ascii = true;
  write_point_file((dir / "out.ply").string(), file, ascii);
  const std::string text = test::read_file(dir / "out.ply");
  EXPECT_NE(text.find("end_header\n0 0 0 0.25 +7\nnan nan nan nan 8\n1 0 0 0 9\n0 1 0 0.125 10\n"), std::string::npos)
      << text;
  const auto expect_refused = [&](const std::string& name, const std::vector<double>& values, ErrorCode code,
                                  const std::string& piece) {
    try {
      file.set_scalar_property(name, values);
      ADD_FAILURE() << name << ": no error";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), code) << e.what();
      EXPECT_NE(std::string(e.what()).find(piece), std::string::npos) << e.what();
    }
  };
  expect_refused("intensity", {1, 2, 3}, ErrorCode::invalid_argument, "no scalar property 'intensity'");
  expect_refused("x", {1, 2, 3}, ErrorCode::invalid_argument, "coordinate or a normal");
  expect_refused("label", {1, 2, 3}, ErrorCode::invalid_input, "integer");
  expect_refused("curvature", {1, 2, 3, 4}, ErrorCode::invalid_argument, "4 values for 3 valid points");
}

TEST(PointFile, FromPointCloud) {
  TempDir dir;
  const PointCloud cloud{{{1, 2, 3}, {4, 5, 6}}, {{0, 0, 1}, {0, 1, 0}}, {0.5, 0.25}};
  const PointFile file(cloud);
  EXPECT_EQ(file.size(), 2u);
  write_point_file((dir / "c.ply").string(), file);
  const PointCloud back = read_point_file((dir / "c.ply").string()).cloud();
  EXPECT_EQ(back.positions, cloud.positions);
  EXPECT_EQ(back.normals, cloud.normals);
  EXPECT_EQ(back.radii, cloud.radii);

  EXPECT_EQ(PointFile().size(), 0u);
  write_point_file((dir / "empty.ply").string(), PointFile());
  EXPECT_EQ(read_point_file((dir / "empty.ply").string()).size(), 0u);
}

TEST(PointFile, CopiesAreIndependent) {
  const PointFile original(PointCloud{{{1, 2, 3}}, {{0, 0, 1}}, {}});
  PointFile copy = original;
  copy.set_normals({{1, 0, 0}});
  EXPECT_EQ(original.cloud().normals[0], (Vec3{0, 0, 1}));
  EXPECT_EQ(copy.cloud().normals[0], (Vec3{1, 0, 0}));
  EXPECT_THROW(copy.element_values(1), Error);
}

}  // namespace
}  // namespace pnf
