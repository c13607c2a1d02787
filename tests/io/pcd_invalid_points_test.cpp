// PCD's invalid points through pnf::PointFile: NaN points are invalid rows that stay in place
// with NaN normals, through PLY too; points with NaN normals are kept as they were.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "pcd_test_files.hpp"
#include "ply_test_files.hpp"
#include "pnf/error.hpp"
#include "pnf/point_file.hpp"
#include "pnf/point_file_header.hpp"

namespace pnf {
namespace {

using test::TempDir;
using test::TestField;

TEST(PcdFile, NanPointsStayInPlaceWithNanNormals) {
  TempDir dir;
  const std::vector<TestField> fields = {{"x", 'F', 4, 1}, {"y", 'F', 4, 1}, {"z", 'F', 4, 1}, {"rgba", 'U', 4, 1}};
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::string rows;
  const float coordinates[6][3] = {{0, 0, 1}, {nan, nan, nan}, {1, 0, 1}, {0, 1, 1}, {nan, 0, 1}, {1, 1, 1.5f}};
  for (int p = 0; p < 6; ++p) {
    for (const float c : coordinates[p]) rows += test::float_bytes(c);
    rows += test::u32_le(0xff000000u + p);
  }
  for (const std::string data : {"ascii", "binary", "binary_compressed"}) {
    SCOPED_TRACE(data);
    const std::string in = (dir / ("in_" + data + ".pcd")).string();
    test::write_file(in, test::test_pcd_header(fields, 3, 2, data) + test::test_body(data, fields, rows));
    PointFile file = read_point_file(in);
    EXPECT_EQ(file.size(), 6u);
    ASSERT_EQ(file.valid_count(), 4u);
    const std::size_t rows_of_points[4] = {0, 2, 3, 5};
    for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(file.row_of_point(i), rows_of_points[i]);
    EXPECT_THROW(file.row_of_point(4), Error);
    const PointCloud cloud = file.cloud();
    ASSERT_EQ(cloud.size(), 4u);
    EXPECT_EQ(cloud.positions[3], (Vec3{1, 1, 1.5}));
    EXPECT_THROW(file.set_normals(std::vector<Vec3>(6, Vec3{0, 0, 1})), Error) << "one normal per valid point";
    file.set_normals({{0, 0, 1}, {0, 0.6, 0.8}, {0.6, 0, 0.8}, {1, 0, 0}});
    write_point_file((dir / "out.pcd").string(), file);
    const PointFile back = read_point_file((dir / "out.pcd").string());
    EXPECT_EQ(back.pcd_header()->data, file.pcd_header()->data);
    EXPECT_EQ(back.pcd_header()->width, 3u);
    EXPECT_EQ(back.pcd_header()->height, 2u);
    ASSERT_EQ(back.valid_count(), 4u);
    const std::vector<unsigned char>& values = back.element_values(0);
    ASSERT_EQ(values.size(), 6u * 28u);
    for (std::size_t p = 0; p < 6; ++p) {
      // x y z rgba unchanged, NaN coordinates included (ascii keeps NaN, not its payload: these
      // are canonical)
      EXPECT_EQ(std::memcmp(values.data() + p * 28, rows.data() + p * 16, 16), 0) << "row " << p;
      float normal[3];
      std::memcpy(normal, values.data() + p * 28 + 16, 12);
      const bool valid = p != 1 && p != 4;
      for (const float n : normal) EXPECT_EQ(std::isnan(n), !valid) << "row " << p;
    }
    EXPECT_EQ(back.cloud().normals[1], (Vec3{0, double(0.6f), double(0.8f)}));
  }
}

// An organised PCD's invalid points written as PLY (pnf's own output of such a file) read back
// as invalid points, in binary and ascii PLY, and go back to PCD in their places; a PLY vertex
// with all three coordinates NaN is one too (PCL's PLY writer); a lone NaN coordinate stays an
// error (PointFileErrors.NonFiniteOrZeroVectors).
TEST(PcdFile, InvalidPointsSurviveTheTripThroughPly) {
  TempDir dir;
  const std::vector<TestField> fields = {{"x", 'F', 4, 1}, {"y", 'F', 4, 1}, {"z", 'F', 4, 1}};
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float coordinates[5][3] = {{0, 0, 1}, {nan, nan, nan}, {1, 0, 1}, {nan, 0, 1}, {1, 1, 1.5f}};
  std::string rows;
  for (const auto& point : coordinates)
    for (const float c : point) rows += test::float_bytes(c);
  const std::string in = (dir / "in.pcd").string();
  test::write_file(in, test::test_pcd_header(fields, 5, 1, "binary") + rows);
  PointFile file = read_point_file(in);
  ASSERT_EQ(file.valid_count(), 3u);
  file.set_normals({{0, 0, 1}, {0, 0.6, 0.8}, {0.6, 0, 0.8}});
  for (const bool ascii : {false, true}) {
    SCOPED_TRACE(ascii ? "ascii PLY" : "binary PLY");
    const std::string ply = (dir / (ascii ? "mid_ascii.ply" : "mid.ply")).string();
    WriteOptions options;
    options.ascii = ascii;
    write_point_file(ply, file, options);
    const PointFile back = read_point_file(ply);
    EXPECT_EQ(back.size(), 5u);
    ASSERT_EQ(back.valid_count(), 3u);
    EXPECT_EQ(back.row_of_point(1), 2u);
    EXPECT_EQ(back.row_of_point(2), 4u);
    EXPECT_EQ(back.cloud().positions, file.cloud().positions);
    EXPECT_EQ(back.cloud().normals, file.cloud().normals);
    write_point_file((dir / "out.pcd").string(), back);
    const PointFile pcd = read_point_file((dir / "out.pcd").string());
    ASSERT_EQ(pcd.valid_count(), 3u);
    EXPECT_EQ(pcd.row_of_point(1), 2u);
    EXPECT_EQ(pcd.cloud().normals, file.cloud().normals);
  }
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
  test::write_file(dir / "pcl.ply", header + "end_header\n0 0 0\nnan nan nan\n1 0 0\n");
  const PointFile pcl = read_point_file((dir / "pcl.ply").string());
  EXPECT_EQ(pcl.size(), 3u);
  EXPECT_EQ(pcl.valid_count(), 2u);
}

// PCL's NormalEstimation leaves NaN normals (and curvature) on valid points with too few
// neighbours. Such a point is kept like an invalid point: in its place, out of cloud() (so out of
// every neighbourhood), written back with NaN normals and counted by without_normals(); through
// PLY too. Read with check_normals false it is an ordinary valid point (for `pnf estimate`). An
// infinite, zero or partly NaN normal is still an error naming the point.
TEST(PcdFile, PointsWithNanNormalsAreKeptAsTheyWere) {
  TempDir dir;
  const std::vector<TestField> fields = {{"x", 'F', 4, 1},        {"y", 'F', 4, 1},        {"z", 'F', 4, 1},
                                         {"normal_x", 'F', 4, 1}, {"normal_y", 'F', 4, 1}, {"normal_z", 'F', 4, 1},
                                         {"curvature", 'F', 4, 1}};
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float values[6][7] = {{0, 0, 1, 0, 0, 1, 0.25f},
                              {1, 0, 1, nan, nan, nan, nan},        // a point without a normal
                              {nan, nan, nan, nan, nan, nan, nan},  // an invalid point
                              {0, 1, 1, 0, 0.6f, 0.8f, 0.5f},
                              {1, 1, 1, nan, nan, nan, nan},  // a point without a normal
                              {2, 1, 1, 0, 0, 1, 0.75f}};
  std::string rows;
  for (const auto& row : values)
    for (const float v : row) rows += test::float_bytes(v);
  constexpr std::size_t kRowBytes = 7 * 4;
  const std::size_t kept_rows[3] = {0, 3, 5};
  for (const std::string data : {"ascii", "binary", "binary_compressed"}) {
    SCOPED_TRACE(data);
    const std::string in = (dir / ("in_" + data + ".pcd")).string();
    test::write_file(in, test::test_pcd_header(fields, 3, 2, data) + test::test_body(data, fields, rows));
    PointFile file = read_point_file(in);
    EXPECT_EQ(file.size(), 6u);
    ASSERT_EQ(file.valid_count(), 3u);
    EXPECT_EQ(file.without_normals(), 2u);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(file.row_of_point(i), kept_rows[i]);
    const PointCloud cloud = file.cloud();
    ASSERT_EQ(cloud.size(), 3u);
    EXPECT_EQ(cloud.positions[1], (Vec3{0, 1, 1}));
    EXPECT_EQ(cloud.normals[1], (Vec3{0, double(0.6f), double(0.8f)}));
    file.set_normals({{0, 0.6, 0.8}, {0.6, 0, 0.8}, {1, 0, 0}});
    const std::string out = (dir / ("out_" + data + ".pcd")).string();
    write_point_file(out, file);
    const PointFile back = read_point_file(out);
    EXPECT_EQ(back.pcd_header()->width, 3u);
    EXPECT_EQ(back.pcd_header()->height, 2u);
    EXPECT_EQ(back.valid_count(), 3u);
    EXPECT_EQ(back.without_normals(), 2u);
    const std::vector<unsigned char>& written = back.element_values(0);
    ASSERT_EQ(written.size(), 6 * kRowBytes);
    for (std::size_t r = 0; r < 6; ++r) {
      float row[7];
      std::memcpy(row, written.data() + r * kRowBytes, kRowBytes);
      const bool kept = r == 0 || r == 3 || r == 5;
      for (int c : {0, 1, 2, 6}) {
        // Positions and curvature as they were (NaN stays NaN).
        if (std::isnan(values[r][c]))
          EXPECT_TRUE(std::isnan(row[c])) << "row " << r << " column " << c;
        else
          EXPECT_EQ(row[c], values[r][c]) << "row " << r << " column " << c;
      }
      for (int c = 3; c < 6; ++c) EXPECT_EQ(std::isnan(row[c]), !kept) << "row " << r << " column " << c;
    }
    EXPECT_EQ(back.cloud().normals[2], (Vec3{1, 0, 0}));

    // Through PLY and back: the same rows are left out.
    const std::string ply = (dir / ("mid_" + data + ".ply")).string();
    write_point_file(ply, back);
    const PointFile from_ply = read_point_file(ply);
    EXPECT_EQ(from_ply.size(), 6u);
    EXPECT_EQ(from_ply.valid_count(), 3u);
    EXPECT_EQ(from_ply.without_normals(), 2u);
    EXPECT_EQ(from_ply.cloud().positions, back.cloud().positions);

    // For a caller that replaces every normal they are valid points.
    ReadOptions unchecked;
    unchecked.check_normals = false;
    const PointFile all = read_point_file(in, unchecked);
    EXPECT_EQ(all.valid_count(), 5u);
    EXPECT_EQ(all.without_normals(), 0u);
  }
  const std::vector<TestField> six(fields.begin(), fields.begin() + 6);
  const std::string header = test::test_pcd_header(six, 3, 1, "ascii");
  for (const auto& [row, piece] : std::vector<std::pair<std::string, std::string>>{
           {"1 0 1 inf 0 1", "point 1: normal component normal_x is +infinity"},
           {"1 0 1 0 0 0", "point 1: the normal is zero-length"},
           {"1 0 1 nan nan 1", "point 1: normal component normal_x is NaN"},
           {"1 inf 1 nan nan nan", "point 1: coordinate y is +infinity"}}) {
    SCOPED_TRACE(row);
    test::write_file(dir / "bad.pcd", header + "0 0 1 0 0 1\n" + row + "\n0 1 1 0 0 1\n");
    try {
      (void)read_point_file((dir / "bad.pcd").string());
      ADD_FAILURE() << "read without an error";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::invalid_input);
      EXPECT_NE(std::string(e.what()).find(piece), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace pnf
