// PCD through pnf::PointFile: hand-made files of every DATA kind and every TYPE/SIZE/COUNT read
// to the same bits and write back bit for bit; field order, WIDTH/HEIGHT, VIEWPOINT and comments
// are kept; normals added or replaced; conversions. Invalid points: pcd_invalid_points_test.cpp.
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

// Every PCD type, COUNT 1 and more, x y z not first: a point of 83 bytes.
const std::vector<TestField> kAllTypes = {
    {"i8", 'I', 1, 2},  {"x", 'F', 4, 1},   {"u8", 'U', 1, 1},  {"i16", 'I', 2, 3}, {"y", 'F', 4, 1},
    {"u16", 'U', 2, 1}, {"i32", 'I', 4, 1}, {"z", 'F', 4, 1},   {"u32", 'U', 4, 1}, {"i64", 'I', 8, 1},
    {"u64", 'U', 8, 2}, {"f64", 'F', 8, 2}, {"f32", 'F', 4, 3},
};

// Rows of random bits for `fields`, except: x y z are ordinary floats, and a NaN elsewhere is
// the canonical quiet NaN (text keeps no NaN payload). The first row holds the extremes.
std::string random_rows(const std::vector<TestField>& fields, std::size_t points, unsigned seed) {
  std::mt19937_64 random(seed);
  std::string rows;
  for (std::size_t p = 0; p < points; ++p) {
    for (const TestField& f : fields) {
      for (std::size_t i = 0; i < f.count; ++i) {
        std::uint64_t bits = random();
        if (p == 0) bits = (i % 2 == 0) ? ~std::uint64_t{0} >> (f.type == 'I' ? 1 : 0) : std::uint64_t{1} << 63;
        if (f.name == "x" || f.name == "y" || f.name == "z") {
          const float v = static_cast<float>(std::int64_t(bits % 2001) - 1000) / 7.0f;
          const double d = v;
          rows += f.size == 4 ? test::float_bytes(v) : std::string(reinterpret_cast<const char*>(&d), 8);
        } else if (f.type == 'F' && f.size == 4) {
          float v;
          const std::uint32_t b32 = static_cast<std::uint32_t>(bits);
          std::memcpy(&v, &b32, 4);
          if (std::isnan(v)) v = std::numeric_limits<float>::quiet_NaN();
          rows += test::float_bytes(v);
        } else if (f.type == 'F') {
          double v;
          std::memcpy(&v, &bits, 8);
          if (std::isnan(v)) v = std::numeric_limits<double>::quiet_NaN();
          rows += std::string(reinterpret_cast<const char*>(&v), 8);
        } else {
          rows += std::string(reinterpret_cast<const char*>(&bits), f.size);
        }
      }
    }
  }
  return rows;
}

std::string as_string(const std::vector<unsigned char>& bytes) { return std::string(bytes.begin(), bytes.end()); }

TEST(PcdFile, EveryTypeAndDataKindReadsAndWritesBackBitForBit) {
  TempDir dir;
  const std::string rows = random_rows(kAllTypes, 7, 17);
  for (const std::string in_data : {"ascii", "binary", "binary_compressed"}) {
    const std::string in = (dir / ("in_" + in_data + ".pcd")).string();
    test::write_file(in, test::test_pcd_header(kAllTypes, 7, 1, in_data) + test::test_body(in_data, kAllTypes, rows));
    const PointFile file = read_point_file(in);
    ASSERT_EQ(file.source_format(), PointFileFormat::pcd);
    ASSERT_NE(file.pcd_header(), nullptr);
    EXPECT_EQ(to_string(file.pcd_header()->data), in_data);
    EXPECT_EQ(file.size(), 7u);
    EXPECT_EQ(file.valid_count(), 7u);
    EXPECT_EQ(as_string(file.element_values(0)), rows) << "read from " << in_data;
    for (const PcdData out_data : {PcdData::ascii, PcdData::binary, PcdData::binary_compressed}) {
      const std::string out = (dir / ("out_" + in_data + "_" + to_string(out_data) + ".pcd")).string();
      WriteOptions options;
      options.pcd_data = out_data;
      write_point_file(out, file, options);
      const PointFile back = read_point_file(out);
      EXPECT_EQ(as_string(back.element_values(0)), rows) << in_data << " -> " << to_string(out_data);
      const PcdHeader& header = *back.pcd_header();
      ASSERT_EQ(header.fields.size(), kAllTypes.size());
      for (std::size_t f = 0; f < kAllTypes.size(); ++f) {
        EXPECT_EQ(header.fields[f].name, kAllTypes[f].name);
        EXPECT_EQ(header.fields[f].type, kAllTypes[f].type);
        EXPECT_EQ(header.fields[f].size, kAllTypes[f].size);
        EXPECT_EQ(header.fields[f].count, kAllTypes[f].count);
      }
    }
  }
}

TEST(PcdFile, BinaryOutputIsTheInputFileByteForByte) {
  TempDir dir;
  const std::vector<TestField> fields = {
      {"x", 'F', 4, 1}, {"y", 'F', 4, 1}, {"z", 'F', 4, 1}, {"_", 'U', 1, 4}, {"rgba", 'U', 4, 1}};
  const std::string rows = random_rows(fields, 6, 3);  // padding bytes random: binary keeps them
  const std::string text = test::test_pcd_header(fields, 3, 2, "binary", "1 2 3 0.5 0.5 0.5 0.5") + rows;
  test::write_file(dir / "in.pcd", text);
  const PointFile file = read_point_file((dir / "in.pcd").string());
  write_point_file((dir / "out.pcd").string(), file);
  EXPECT_EQ(test::read_file(dir / "out.pcd"), text);
}

TEST(PcdFile, PaddingIsLeftOutOfCompressedAndAsciiDataAsPclDoes) {
  TempDir dir;
  const std::vector<TestField> fields = {{"x", 'F', 4, 1}, {"_", 'U', 1, 4}, {"y", 'F', 4, 1}, {"z", 'F', 4, 1}};
  std::string rows = random_rows(fields, 4, 5);
  test::write_file(dir / "in.pcd", test::test_pcd_header(fields, 4, 1, "binary") + rows);
  const PointFile file = read_point_file((dir / "in.pcd").string());
  WriteOptions compressed;
  compressed.pcd_data = PcdData::binary_compressed;
  write_point_file((dir / "c.pcd").string(), file, compressed);
  const std::string c = test::read_file(dir / "c.pcd");
  EXPECT_NE(c.find("FIELDS x _ y z\nSIZE 4 1 4 4\nTYPE F U F F\nCOUNT 1 4 1 1\n"), std::string::npos) << c;
  for (std::size_t p = 0; p < 4; ++p) rows.replace(p * 16 + 4, 4, 4, '\0');  // padding reads back as zero
  EXPECT_EQ(as_string(read_point_file((dir / "c.pcd").string()).element_values(0)), rows);

  WriteOptions ascii;
  ascii.ascii = true;
  write_point_file((dir / "a.pcd").string(), file, ascii);
  const std::string a = test::read_file(dir / "a.pcd");
  EXPECT_NE(a.find("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"), std::string::npos) << a;
  EXPECT_NE(a.find("DATA ascii\n"), std::string::npos) << a;
}

TEST(PcdFile, HeaderIsKeptAndDataDefaultsToTheInputs) {
  TempDir dir;
  const std::vector<TestField> fields = {
      {"z", 'F', 4, 1}, {"intensity", 'U', 2, 1}, {"y", 'F', 8, 1}, {"x", 'F', 4, 1}};
  const std::string rows = random_rows(fields, 6, 9);
  const std::string header =
      "# .PCD v0.7 - Point Cloud Data file format\n# scanner: lidar 7\nVERSION 0.7\n"
      "FIELDS z intensity y x\nSIZE 4 2 8 4\nTYPE F U F F\nCOUNT 1 1 1 1\nWIDTH 3\nHEIGHT 2\n"
      "VIEWPOINT 0.25 -1.5 3 0.7071 0 0.7071 0\nPOINTS 6\nDATA binary_compressed\n";
  test::write_file(dir / "in.pcd", header + test::test_compressed_body(fields, rows));
  const PointFile file = read_point_file((dir / "in.pcd").string());
  const PcdHeader& in = *file.pcd_header();
  EXPECT_EQ(in.width, 3u);
  EXPECT_EQ(in.height, 2u);
  EXPECT_EQ(in.points, 6u);
  const std::array<double, 7> viewpoint = {0.25, -1.5, 3, 0.7071, 0, 0.7071, 0};
  EXPECT_EQ(in.viewpoint, viewpoint);
  ASSERT_EQ(in.comments.size(), 2u);
  EXPECT_EQ(in.comments[1], "# scanner: lidar 7");

  write_point_file((dir / "out.pcd").string(), file);
  const std::string out = test::read_file(dir / "out.pcd");
  EXPECT_EQ(out.substr(0, header.size()), header) << "the header is written back as read";
  const PointFile back = read_point_file((dir / "out.pcd").string());
  EXPECT_EQ(back.pcd_header()->data, PcdData::binary_compressed);
  EXPECT_EQ(as_string(back.element_values(0)), rows);
  // positions come from fields x y z wherever they are, y in double
  const PointCloud cloud = back.cloud();
  double y;
  std::memcpy(&y, rows.data() + 6, 8);
  EXPECT_EQ(cloud.positions[0][1], y);

  WriteOptions ascii;
  ascii.ascii = true;
  write_point_file((dir / "ascii.pcd").string(), file, ascii);
  EXPECT_EQ(read_point_file((dir / "ascii.pcd").string()).pcd_header()->data, PcdData::ascii);
  WriteOptions binary;
  binary.ascii = true;  // pcd_data wins over ascii
  binary.pcd_data = PcdData::binary;
  write_point_file((dir / "binary.pcd").string(), file, binary);
  EXPECT_EQ(read_point_file((dir / "binary.pcd").string()).pcd_header()->data, PcdData::binary);
}

TEST(PcdFile, PackedColourKeepsItsBitsInAscii) {
  TempDir dir;
  const std::vector<TestField> fields = {{"x", 'F', 4, 1}, {"y", 'F', 4, 1}, {"z", 'F', 4, 1}, {"rgb", 'F', 4, 1}};
  std::string rows;
  for (const std::uint32_t colour : {0xffff8000u, 0x00102030u, 0x7fc00001u}) {  // two are NaN as floats
    rows += test::float_bytes(1) + test::float_bytes(2) + test::float_bytes(3) + test::u32_le(colour);
  }
  test::write_file(dir / "in.pcd", test::test_pcd_header(fields, 3, 1, "binary") + rows);
  const PointFile file = read_point_file((dir / "in.pcd").string());
  WriteOptions ascii;
  ascii.pcd_data = PcdData::ascii;
  write_point_file((dir / "a.pcd").string(), file, ascii);
  const std::string text = test::read_file(dir / "a.pcd");
  EXPECT_NE(text.find("TYPE F F F U\n"), std::string::npos) << "PCL's ascii convention: " << text;
  EXPECT_NE(text.find("1 2 3 4294934528\n"), std::string::npos) << text;
  EXPECT_EQ(as_string(read_point_file((dir / "a.pcd").string()).element_values(0)), rows);
  // An F rgb written as digits (as PCL's ascii writer does) reads as its bits.
  test::write_file(dir / "digits.pcd", test::test_pcd_header(fields, 1, 1, "ascii") + "1 2 3 4294934528\n");
  EXPECT_EQ(as_string(read_point_file((dir / "digits.pcd").string()).element_values(0)), rows.substr(0, 16));
}

TEST(PcdFile, NormalsAreAddedOrReplacedAndCurvatureKept) {
  TempDir dir;
  const std::vector<TestField> with = {{"x", 'F', 4, 1},        {"y", 'F', 4, 1},        {"z", 'F', 4, 1},
                                       {"normal_x", 'F', 8, 1}, {"normal_y", 'F', 8, 1}, {"normal_z", 'F', 8, 1},
                                       {"curvature", 'F', 4, 1}};
  std::string rows;
  for (int p = 0; p < 3; ++p) {
    rows += test::float_bytes(float(p)) + test::float_bytes(0) + test::float_bytes(0);
    const double normal[3] = {0, 0, 1};
    rows += std::string(reinterpret_cast<const char*>(normal), 24) + test::float_bytes(0.125f * p);
  }
  test::write_file(dir / "with.pcd", test::test_pcd_header(with, 3, 1, "ascii") + test::test_ascii_body(with, rows));
  PointFile file = read_point_file((dir / "with.pcd").string());
  ASSERT_TRUE(file.has_normals());
  file.set_normals({{1, 0, 0}, {0, 1, 0}, {0, 0, -1}});
  write_point_file((dir / "out.pcd").string(), file);
  const PointFile back = read_point_file((dir / "out.pcd").string());
  EXPECT_EQ(back.pcd_header()->fields.size(), 7u) << "no fields added";
  EXPECT_EQ(back.pcd_header()->fields[3].size, 8u) << "normals keep their type";
  EXPECT_EQ(back.cloud().normals[2], (Vec3{0, 0, -1}));
  float curvature;
  std::memcpy(&curvature, back.element_values(0).data() + 2 * 40 + 36, 4);
  EXPECT_EQ(curvature, 0.25f);

  const std::vector<TestField> bare = {{"x", 'F', 4, 1}, {"y", 'F', 4, 1}, {"z", 'F', 4, 1}};
  test::write_file(dir / "bare.pcd", test::test_pcd_header(bare, 3, 1, "binary") + std::string(36, '\0'));
  PointFile added = read_point_file((dir / "bare.pcd").string());
  added.set_normals({{1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
  write_point_file((dir / "added.pcd").string(), added);
  EXPECT_NE(test::read_file(dir / "added.pcd")
                .find("FIELDS x y z normal_x normal_y normal_z\nSIZE 4 4 4 4 4 4\n"
                      "TYPE F F F F F F\n"),
            std::string::npos);
}

TEST(PcdFile, Version06AndDefaultsAreRead) {
  TempDir dir;
  // v0.6: no VIEWPOINT, here also no COUNT, no HEIGHT, and COLUMNS for FIELDS.
  test::write_file(dir / "old.pcd",
                   "# .PCD v.6 - Point Cloud Data file format\nVERSION .6\nCOLUMNS x y z\n"
                   "SIZE 4 4 4\nTYPE F F F\nWIDTH 2\nPOINTS 2\nDATA ascii\n1 2 3\n4 5 6\n");
  const PointFile file = read_point_file((dir / "old.pcd").string());
  EXPECT_EQ(file.pcd_header()->version, ".6");
  EXPECT_EQ(file.pcd_header()->height, 1u);
  EXPECT_EQ(file.cloud().positions[1], (Vec3{4, 5, 6}));
  write_point_file((dir / "new.pcd").string(), file);
  const std::string text = test::read_file(dir / "new.pcd");
  EXPECT_EQ(text.rfind("# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\n"
                       "TYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n",
                       0),
            0u)
      << text;
}

TEST(PcdFile, OtherFormatsConvertToAndFromPcd) {
  TempDir dir;
  PointCloud cloud;
  cloud.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  cloud.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  write_point_file((dir / "in.ply").string(), PointFile(cloud));
  write_point_file((dir / "out.pcd").string(), read_point_file((dir / "in.ply").string()));
  const PointFile pcd = read_point_file((dir / "out.pcd").string());
  EXPECT_EQ(pcd.pcd_header()->fields[3].name, "normal_x");
  EXPECT_EQ(pcd.pcd_header()->data, PcdData::binary);
  EXPECT_EQ(pcd.cloud().positions, cloud.positions);
  EXPECT_EQ(pcd.cloud().normals, cloud.normals);
  write_point_file((dir / "back.ply").string(), pcd);
  EXPECT_EQ(read_point_file((dir / "back.ply").string()).cloud().normals, cloud.normals);

  // A PLY list cannot go to PCD, a 64-bit integer cannot go to PLY; nothing is written.
  test::write_file(dir / "list.ply",
                   "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                   "property float z\nproperty list uchar int ids\nend_header\n0 0 0 2 5 6\n");
  try {
    write_point_file((dir / "list.pcd").string(), read_point_file((dir / "list.ply").string()));
    ADD_FAILURE() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
    EXPECT_NE(std::string(e.what()).find("'ids' is a list"), std::string::npos) << e.what();
  }
  const std::vector<TestField> wide = {{"x", 'F', 4, 1}, {"y", 'F', 4, 1}, {"z", 'F', 4, 1}, {"stamp", 'U', 8, 1}};
  test::write_file(dir / "wide.pcd", test::test_pcd_header(wide, 1, 1, "ascii") + "0 0 0 18446744073709551615\n");
  try {
    write_point_file((dir / "wide.ply").string(), read_point_file((dir / "wide.pcd").string()));
    ADD_FAILURE() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'stamp' is uint64"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "list.pcd"));
  EXPECT_FALSE(std::filesystem::exists(dir / "wide.ply"));
}

}  // namespace
}  // namespace pnf
