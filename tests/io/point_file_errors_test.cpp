// Errors of pnf::read_point_file / PointFile: each names the file and the place (header line,
// element and line or row, vertex) and says what is wrong, with the right ErrorCode.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

#include "ply_test_files.hpp"
#include "pnf/error.hpp"
#include "pnf/point_file.hpp"

namespace pnf {
namespace {

using test::TempDir;

constexpr const char* kXyzHeader =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nproperty float nx\nproperty float ny\nproperty float nz\nend_header\n";

std::string binary_header(const std::string& encoding, std::uint64_t vertices) {
  return "ply\nformat " + encoding + " 1.0\nelement vertex " + std::to_string(vertices) +
         "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
}

std::string floats(std::initializer_list<float> values) {
  return std::string(reinterpret_cast<const char*>(values.begin()), values.size() * sizeof(float));
}

// Writes `contents` to `name` in `dir`, reads it, and checks that the read fails with `code`
// and a message containing the file name and every one of `parts`.
void expect_read_error(const TempDir& dir, const std::string& name, const std::string& contents, ErrorCode code,
                       const std::vector<std::string>& parts) {
  test::write_file(dir / name, contents);
  const std::string path = (dir / name).string();
  try {
    read_point_file(path);
    ADD_FAILURE() << name << ": expected an error containing '" << parts.at(0) << "'";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_EQ(error.code(), code) << message;
    EXPECT_NE(message.find(path), std::string::npos) << message;
    for (const std::string& part : parts) {
      EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
    }
    EXPECT_EQ(message.find('\n'), std::string::npos) << "not one line: " << message;
  }
}

void expect_invalid_input(const TempDir& dir, const std::string& name, const std::string& contents,
                          const std::vector<std::string>& parts) {
  expect_read_error(dir, name, contents, ErrorCode::invalid_input, parts);
}

TEST(PointFileErrors, MissingOrUnreadableFileIsIo) {
  TempDir dir;
  for (const char* name : {"missing.ply", "missing.xyz"}) {
    const std::string path = (dir / name).string();
    try {
      read_point_file(path);
      ADD_FAILURE() << "expected an error";
    } catch (const Error& error) {
      EXPECT_EQ(error.code(), ErrorCode::io);
      EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
      EXPECT_NE(std::string(error.what()).find("No such file or directory"), std::string::npos) << error.what();
    }
  }
  std::filesystem::create_directory(dir / "folder.ply");
  try {
    read_point_file((dir / "folder.ply").string());
    ADD_FAILURE() << "expected an error";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::io);
    EXPECT_NE(std::string(error.what()).find("Is a directory"), std::string::npos) << error.what();
  }
}

TEST(PointFileErrors, UnknownExtensionIsInvalidArgument) {
  TempDir dir;
  expect_read_error(dir, "points.off", "OFF\n", ErrorCode::invalid_argument, {"'.off'"});
  expect_read_error(dir, "points", "1 2 3\n", ErrorCode::invalid_argument, {"extension"});
  try {
    write_point_file((dir / "out.obj").string(), PointFile());
    ADD_FAILURE() << "expected an error";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::invalid_argument);
    EXPECT_NE(std::string(error.what()).find("out.obj"), std::string::npos);
  }
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"points", "points.off"}));
}

TEST(PointFileErrors, MalformedHeader) {
  TempDir dir;
  expect_invalid_input(dir, "empty.ply", "", {"empty"});
  expect_invalid_input(dir, "magic.ply", "plyx\nformat ascii 1.0\n", {"not a PLY file"});
  expect_invalid_input(dir, "no_end.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n",
                       {"no end_header"});
  expect_invalid_input(dir, "type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float16 x\nend_header\n",
                       {"header line 4", "unknown property type 'float16'"});
  expect_invalid_input(dir, "list_type.ply",
                       "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                       "element face 1\nproperty list float int vertex_indices\nend_header\n",
                       {"header line 6", "'float' is not an integer type"});
  expect_invalid_input(dir, "format.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n",
                       {"header line 2", "unknown format 'binary_middle_endian'"});
  expect_invalid_input(dir, "count.ply", "ply\nformat ascii 1.0\nelement vertex -3\nend_header\n",
                       {"header line 3", "'-3'", "not a non-negative integer"});
  expect_invalid_input(dir, "orphan.ply", "ply\nformat ascii 1.0\nproperty float x\nend_header\n",
                       {"header line 3", "property before any element"});
  expect_invalid_input(dir, "keyword.ply", "ply\nformat ascii 1.0\nelements vertex 1\n",
                       {"header line 3", "unknown keyword 'elements'"});
  expect_invalid_input(dir, "no_format.ply", "ply\nend_header\n", {"before any format line"});
  // Binary data where the header should end: a line too long to be a header line.
  expect_invalid_input(dir, "binary_junk.ply", "ply\nformat binary_little_endian 1.0\n" + std::string(70000, 'x'),
                       {"header line 3", "no end_header"});
}

TEST(PointFileErrors, MissingPositionsOrPartialNormals) {
  TempDir dir;
  expect_invalid_input(dir, "no_vertex.ply",
                       "ply\nformat ascii 1.0\nelement face 0\n"
                       "property list uchar int vertex_indices\nend_header\n",
                       {"no 'vertex' element"});
  expect_invalid_input(dir, "no_z.ply",
                       "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                       "property float y\nend_header\n1 2\n",
                       {"no 'z' property"});
  expect_invalid_input(dir, "partial.ply",
                       "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                       "property float y\nproperty float z\nproperty float nx\nproperty float ny\n"
                       "end_header\n1 2 3 0 1\n",
                       {"only some of 'nx'"});
}

TEST(PointFileErrors, BinaryCountsAreCheckedBeforeAllocating) {
  TempDir dir;
  // 2^40 vertices of 12 bytes: allocating them would need 12 TiB.
  const std::uint64_t huge = std::uint64_t{1} << 40;
  expect_invalid_input(dir, "huge.ply", binary_header("binary_little_endian", huge) + floats({1, 2, 3}),
                       {"element 'vertex'", "1099511627776 rows", "only 12 bytes remain"});
  // A list claiming far more items than the file holds.
  std::string face =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
      "property float y\nproperty float z\nelement face 2\n"
      "property list int int vertex_indices\nend_header\n" +
      floats({1, 2, 3});
  const std::int32_t one_face[4] = {3, 0, 0, 0};
  face.append(reinterpret_cast<const char*>(one_face), sizeof one_face);
  const std::int32_t huge_count = 2000000000;
  face.append(reinterpret_cast<const char*>(&huge_count), sizeof huge_count);
  expect_invalid_input(dir, "huge_list.ply", face, {"element 'face' row 1", "2000000000 items", "only 0 bytes remain"});
  const std::int32_t negative_count = -1;
  face.resize(face.size() - 4);
  face.append(reinterpret_cast<const char*>(&negative_count), sizeof negative_count);
  expect_invalid_input(dir, "negative_list.ply", face, {"element 'face' row 1", "negative count"});
}

TEST(PointFileErrors, TruncatedBinary) {
  TempDir dir;
  // Ends in the middle of vertex 1 (index from 0).
  expect_invalid_input(dir, "mid_vertex.ply", binary_header("binary_big_endian", 3) + floats({1, 2, 3, 4}),
                       {"element 'vertex' row 1", "ends inside this row"});
  // Ends exactly after vertex 1.
  expect_invalid_input(dir, "between.ply", binary_header("binary_little_endian", 3) + floats({1, 2, 3, 4, 5, 6}),
                       {"element 'vertex' row 2", "ends before this row"});
  // Ends inside a list of row 0 of the second element.
  std::string face =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nproperty uchar flag\nend_header\n" +
      floats({1, 2, 3}) + std::string("\x03\0\0\0\0\0\0\0\0\0\0\0\0", 13);
  expect_invalid_input(dir, "mid_face.ply", face, {"element 'face' row 0", "ends inside"});
  // More data than the header declares.
  expect_invalid_input(dir, "extra.ply", binary_header("binary_little_endian", 1) + floats({1, 2, 3, 4}),
                       {"4 bytes of data after the last element 'vertex'"});
}

TEST(PointFileErrors, MalformedAsciiBody) {
  TempDir dir;
  const std::string header = kXyzHeader;  // vertex rows start at line 11
  expect_invalid_input(dir, "token.ply", header + "1 2 3 0 0 1\n1 two 3 0 0 1\n",
                       {"line 12", "element 'vertex' row 1", "property 'y'", "'two'", "not a number"});
  expect_invalid_input(dir, "short.ply", header + "1 2 3 0 0 1\n\n1 2 3 0 0\n",
                       {"line 13", "element 'vertex' row 1", "expected 6 values, found 5"});
  expect_invalid_input(dir, "long.ply", header + "1 2 3 0 0 1 7\n",
                       {"line 11", "element 'vertex' row 0", "expected 6 values, found 7"});
  expect_invalid_input(dir, "ends.ply", header + "1 2 3 0 0 1\n1 2 3 0 0 1\n",
                       {"line 12", "ends after 2 of 3 rows of element 'vertex'"});
  expect_invalid_input(dir, "trailing.ply", header + "1 2 3 0 0 1\n1 2 3 0 0 1\n1 2 3 0 0 1\n9\n",
                       {"line 14", "data after the last element"});
  const std::string face_header =
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
      "1 2 3\n";
  expect_invalid_input(dir, "list.ply", face_header + "3 0 0 0\n3 0 0\n",
                       {"line 12", "element 'face' row 1", "expected 4 values, found 3"});
  expect_invalid_input(dir, "range.ply", face_header + "3 0 0 0\n300 0 0\n",
                       {"line 12", "element 'face' row 1", "'300' is out of range for uchar"});
  expect_invalid_input(dir, "fraction.ply", face_header + "3 0 0.5 0\n3 0 0 0\n",
                       {"line 11", "element 'face' row 0", "'0.5' is not an integer"});
}

TEST(PointFileErrors, NonFiniteOrZeroVectors) {
  TempDir dir;
  const std::string header = kXyzHeader;
  expect_invalid_input(dir, "nan.ply", header + "1 2 3 0 0 1\n1 2 3 0 0 1\n1 nan 3 0 0 1\n",
                       {"line 13", "vertex 2", "coordinate y is NaN"});
  // Without normals too: only all three coordinates NaN mark an invalid point (PcdFile tests).
  expect_invalid_input(dir, "nan_no_normals.ply",
                       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                       "property float z\nend_header\n0 0 0\nnan 0 0\n1 0 0\n",
                       {"line 9", "vertex 1", "coordinate x is NaN"});
  expect_invalid_input(dir, "inf.ply", header + "1 2 3 0 0 1\n1 2 3 0 -inf 1\n1 2 3 0 0 1\n",
                       {"line 12", "vertex 1", "normal component ny is -infinity"});
  expect_invalid_input(dir, "zero.ply", header + "1 2 3 0 0 1\n1 2 3 0 0 1\n1 2 3 0 0 -0\n",
                       {"line 13", "vertex 2", "zero-length"});
  // Binary: the vertex index, no line.
  const float inf = std::numeric_limits<float>::infinity();
  expect_invalid_input(dir, "inf_binary.ply", binary_header("binary_little_endian", 2) + floats({1, 2, 3, inf, 5, 6}),
                       {"vertex 1", "coordinate x is +infinity"});
  expect_invalid_input(dir, "nan.xyz", "1 2 3\n\n4 nan 6\n", {"line 3", "vertex 1", "NaN"});
  expect_invalid_input(dir, "zero.pwn", "1 2 3 0 0 1\n4 5 6 0 0 0\n", {"line 2", "vertex 1", "zero-length"});
}

TEST(PointFileErrors, MalformedTextFormats) {
  TempDir dir;
  expect_invalid_input(dir, "four.xyz", "# header\n1 2 3 4\n",
                       {"line 2", "expected 3 values (x y z) or 6 (x y z nx ny nz), found 4"});
  expect_invalid_input(dir, "mixed.xyz", "1 2 3\n4 5 6 0 0 1\n", {"line 2", "expected 3 values (x y z), found 6"});
  expect_invalid_input(dir, "short.xyzn", "1 2 3 0 0 1\n1 2 3\n",
                       {"line 2", "expected 6 values (x y z nx ny nz), found 3"});
  expect_invalid_input(dir, "word.pwn", "1 2 3 0 0 1\n1 2 3 0 zero 1\n", {"line 2", "'zero' is not a number"});
}

TEST(PointFileErrors, SetNormalsChecksItsInput) {
  PointFile file(PointCloud{{{1, 2, 3}, {4, 5, 6}}, {}, {}});
  const auto expect_argument_error = [&](const std::vector<Vec3>& normals, const std::string& part) {
    try {
      file.set_normals(normals);
      ADD_FAILURE() << "expected an error containing " << part;
    } catch (const Error& error) {
      EXPECT_EQ(error.code(), ErrorCode::invalid_argument);
      EXPECT_NE(std::string(error.what()).find(part), std::string::npos) << error.what();
    }
  };
  expect_argument_error({{0, 0, 1}}, "1 normals for 2 vertices");
  expect_argument_error({{0, 0, 1}, {0, 0, 0}}, "normal 1 is zero-length");
  expect_argument_error({{0, 0, 1}, {0, std::nan(""), 1}}, "normal 1 is not finite");
  EXPECT_FALSE(file.has_normals());

  EXPECT_THROW(PointFile(PointCloud{{{1, 2, 3}}, {{0, 0, 1}, {0, 0, 1}}, {}}), Error);
  EXPECT_THROW(PointFile(PointCloud{{{1, 2, std::nan("")}}, {}, {}}), Error);
}

TEST(PointFileErrors, IntegerNormalsCannotBeReplaced) {
  TempDir dir;
  test::write_file(dir / "int_normals.ply",
                   "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                   "property float z\nproperty char nx\nproperty char ny\nproperty char nz\n"
                   "end_header\n1 2 3 0 0 1\n");
  PointFile file = read_point_file((dir / "int_normals.ply").string());
  EXPECT_EQ(file.cloud().normals[0], (Vec3{0, 0, 1}));
  try {
    file.set_normals({{1, 0, 0}});
    ADD_FAILURE() << "expected an error";
  } catch (const Error& error) {
    EXPECT_EQ(error.code(), ErrorCode::invalid_input);
    EXPECT_NE(std::string(error.what()).find("'nx' is declared 'char'"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace pnf
