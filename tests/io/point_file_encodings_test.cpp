// Round trips of pnf::read_point_file / write_point_file in every PLY encoding: every scalar
// type, lists, unknown properties and elements kept byte for byte, normals replaced or added, PCL
// normal names.
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

using test::Column;
using test::Element;
using test::Encoding;
using test::PlyModel;
using test::TempDir;

// A vertex element using every scalar type under both spellings, positions of three different
// types, normals in float and double, a radius, and a list inside the vertex; then a face
// element with lists (one empty), an element mixing scalars and lists, an element with no
// rows and one with no properties. Tokens include spellings a writer would not produce ("+7",
// "1.50", "1e3") so that keeping the original text is visible.
PlyModel rich_model() {
  PlyModel model;
  model.comments = {"comment written by the pnf io tests", "obj_info num_cols 512", "comment  two  spaces "};
  Element vertex;
  vertex.name = "vertex";
  vertex.columns = {{"float", "x", ""},
                    {"double", "y", ""},
                    {"int", "z", ""},
                    {"uchar", "red", ""},
                    {"float", "nx", ""},
                    {"float32", "ny", ""},
                    {"double", "nz", ""},
                    {"char", "c", ""},
                    {"uchar", "uc", ""},
                    {"short", "s", ""},
                    {"ushort", "us", ""},
                    {"int", "i", ""},
                    {"uint", "ui", ""},
                    {"float", "f", ""},
                    {"double", "d", ""},
                    {"int8", "i8", ""},
                    {"uint8", "u8", ""},
                    {"int16", "i16", ""},
                    {"uint16", "u16", ""},
                    {"int32", "i32", ""},
                    {"uint32", "u32", ""},
                    {"float32", "f32", ""},
                    {"float64", "f64", ""},
                    {"float", "radius", ""},
                    {"float64", "samples", "uint16"}};
  vertex.rows = {
      {"0.5",
       "1.25",
       "-3",
       "255",
       "0",
       "0",
       "1",
       "-128",
       "255",
       "-32768",
       "65535",
       "-2147483648",
       "4294967295",
       "3.4028235e38",
       "1.7976931348623157e308",
       "127",
       "0",
       "32767",
       "0",
       "2147483647",
       "0",
       "1.17549435e-38",
       "4.9406564584124654e-324",
       "0.01",
       "2",
       "1.5",
       "-2.5"},
      {"1.50",  "0.1", "+7", "0", "0.6", "-0.8", "0",  "0", "0",   "0",   "0",    "0", "0",
       "1e-45", "-0",  "-1", "1", "-1",  "1",    "-1", "1", "nan", "inf", "0.02", "0"},
      {"-1e3",
       "-1e-300",
       "2147483647",
       "7",
       "0.1",
       "0.2",
       "0.3",
       "1",
       "2",
       "3",
       "4",
       "5",
       "6",
       "-inf",
       "1e3",
       "-128",
       "255",
       "-32768",
       "65535",
       "-2147483648",
       "4294967295",
       "-3.4028235e38",
       "2.2250738585072014e-308",
       "1",
       "3",
       "0",
       "1",
       "2"},
  };
  Element face;
  face.name = "face";
  face.columns = {{"int", "vertex_indices", "uchar"}};
  face.rows = {{"3", "0", "1", "2"}, {"0"}, {"4", "2", "1", "0", "2"}};
  Element edge;
  edge.name = "edge";
  edge.columns = {{"int", "vertex1", ""},
                  {"int32", "vertex2", ""},
                  {"uint32", "flags", "int8"},
                  {"uchar", "red", ""},
                  {"short", "tags", "uint"}};
  edge.rows = {{"0", "1", "2", "7", "4294967295", "255", "1", "-5"}, {"1", "2", "0", "0", "2", "-32768", "32767"}};
  Element material;
  material.name = "material";
  material.columns = {{"float", "shininess", ""}};
  Element marker;
  marker.name = "marker";
  marker.rows = {{}, {}};
  model.elements = {vertex, face, edge, material, marker};
  return model;
}

std::string encoding_name(Encoding encoding) {
  switch (encoding) {
    case Encoding::ascii: return "ascii";
    case Encoding::little_endian: return "binary_little_endian";
    case Encoding::big_endian: return "binary_big_endian";
  }
  return "";
}

PlyEncoding ply_encoding(Encoding encoding) {
  switch (encoding) {
    case Encoding::ascii: return PlyEncoding::ascii;
    case Encoding::little_endian: return PlyEncoding::binary_little_endian;
    case Encoding::big_endian: break;
  }
  return PlyEncoding::binary_big_endian;
}

std::size_t column_index(const Element& element, const std::string& name) {
  for (std::size_t c = 0; c < element.columns.size(); ++c) {
    if (element.columns[c].name == name) return c;
  }
  ADD_FAILURE() << "no column " << name;
  return 0;
}

// A vertex token read as the double pnf should give for it: rounded to float for float
// columns. Valid for the scalar columns before the vertex's list (tokens and columns align).
double model_value(const Element& element, std::size_t row, const std::string& name) {
  const std::size_t c = column_index(element, name);
  const std::string& type = element.columns[c].type;
  const std::string& token = element.rows[row][c];
  if (type == "float" || type == "float32") return std::strtof(token.c_str(), nullptr);
  return std::strtod(token.c_str(), nullptr);
}

// Shortest text of a value in the type of a column, as pnf writes it.
std::string shortest(const std::string& type, double value) {
  char buffer[64];
  const auto result = (type == "float" || type == "float32")
                          ? std::to_chars(buffer, buffer + sizeof buffer, static_cast<float>(value))
                          : std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

void expect_header_matches(const PlyHeader& header, const PlyModel& model) {
  ASSERT_EQ(header.elements.size(), model.elements.size());
  for (std::size_t e = 0; e < model.elements.size(); ++e) {
    const PlyElement& element = header.elements[e];
    const Element& expected = model.elements[e];
    EXPECT_EQ(element.name, expected.name);
    EXPECT_EQ(element.count, expected.rows.size()) << expected.name;
    ASSERT_EQ(element.properties.size(), expected.columns.size()) << expected.name;
    for (std::size_t p = 0; p < expected.columns.size(); ++p) {
      const PlyProperty& property = element.properties[p];
      const Column& column = expected.columns[p];
      EXPECT_EQ(property.name, column.name);
      EXPECT_EQ(property.type_name, column.type) << column.name;
      EXPECT_EQ(property.is_list, !column.count_type.empty()) << column.name;
      if (property.is_list) {
        EXPECT_EQ(property.count_type_name, column.count_type);
      }
    }
  }
  ASSERT_EQ(header.comments.size(), model.comments.size());
  for (std::size_t i = 0; i < model.comments.size(); ++i) {
    const PlyComment& comment = header.comments[i];
    EXPECT_EQ(comment.keyword + " " + comment.text, model.comments[i]);
  }
}

void expect_same_values(const PointFile& actual, const PointFile& expected) {
  ASSERT_EQ(actual.header().elements.size(), expected.header().elements.size());
  for (std::size_t e = 0; e < expected.header().elements.size(); ++e) {
    EXPECT_EQ(actual.element_values(e), expected.element_values(e)) << "element " << expected.header().elements[e].name;
  }
}

class EveryEncoding : public ::testing::TestWithParam<Encoding> {};

TEST_P(EveryEncoding, ReadsEveryScalarTypeAndList) {
  TempDir dir;
  const PlyModel model = rich_model();
  test::write_file(dir / "in.ply", test::ply_text(model, GetParam()));
  const PointFile file = read_point_file((dir / "in.ply").string());

  EXPECT_EQ(file.source_format(), PointFileFormat::ply);
  EXPECT_EQ(file.header().encoding, ply_encoding(GetParam()));
  EXPECT_EQ(file.header().version, "1.0");
  expect_header_matches(file.header(), model);
  for (std::size_t e = 0; e < model.elements.size(); ++e) {
    EXPECT_EQ(file.element_values(e), test::element_bytes(model.elements[e])) << "element " << model.elements[e].name;
  }

  const Element& vertex = model.elements[0];
  const PointCloud cloud = file.cloud();
  ASSERT_EQ(cloud.size(), 3u);
  ASSERT_TRUE(cloud.has_normals());
  ASSERT_TRUE(cloud.has_radii());
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(cloud.positions[i][0], model_value(vertex, i, "x"));
    EXPECT_EQ(cloud.positions[i][1], model_value(vertex, i, "y"));
    EXPECT_EQ(cloud.positions[i][2], model_value(vertex, i, "z"));
    EXPECT_EQ(cloud.normals[i][0], model_value(vertex, i, "nx"));
    EXPECT_EQ(cloud.normals[i][1], model_value(vertex, i, "ny"));
    EXPECT_EQ(cloud.normals[i][2], model_value(vertex, i, "nz"));
    EXPECT_EQ(cloud.radii[i], model_value(vertex, i, "radius"));
  }
}

TEST_P(EveryEncoding, WritesEverythingBackExactly) {
  TempDir dir;
  const PlyModel model = rich_model();
  test::write_file(dir / "in.ply", test::ply_text(model, GetParam()));
  const PointFile file = read_point_file((dir / "in.ply").string());

  // Binary output is binary_little_endian: the same file for a little-endian source, every
  // value swapped back for a big-endian one, every token converted exactly for ascii.
  write_point_file((dir / "out_binary.ply").string(), file, WriteOptions{});
  EXPECT_EQ(test::read_file(dir / "out_binary.ply"), test::ply_text(model, Encoding::little_endian));

  write_point_file((dir / "out_ascii.ply").string(), file, WriteOptions{true});
  if (GetParam() == Encoding::ascii) {
    // Every token's original text, "+7" and "1.50" included.
    EXPECT_EQ(test::read_file(dir / "out_ascii.ply"), test::ply_text(model, Encoding::ascii));
  }
  const PointFile ascii = read_point_file((dir / "out_ascii.ply").string());
  EXPECT_EQ(ascii.header().encoding, PlyEncoding::ascii);
  expect_header_matches(ascii.header(), model);
  expect_same_values(ascii, file);

  // And back again from the converted files.
  write_point_file((dir / "again.ply").string(), ascii, WriteOptions{});
  EXPECT_EQ(test::read_file(dir / "again.ply"), test::ply_text(model, Encoding::little_endian));
}

TEST_P(EveryEncoding, SetNormalsChangesOnlyTheNormals) {
  TempDir dir;
  const PlyModel model = rich_model();
  test::write_file(dir / "in.ply", test::ply_text(model, GetParam()));
  PointFile file = read_point_file((dir / "in.ply").string());

  const std::vector<Vec3> normals = {{0.1, 0.2, 0.3}, {-1.0 / 3, 2.0 / 3, 0.5}, {0, 0, -1}};
  file.set_normals(normals);

  // Normals are stored in their declared types: nx and ny are float, nz double.
  PlyModel expected = model;
  Element& vertex = expected.elements[0];
  const char* names[3] = {"nx", "ny", "nz"};
  for (std::size_t i = 0; i < normals.size(); ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      const std::size_t c = column_index(vertex, names[axis]);
      vertex.rows[i][c] = shortest(vertex.columns[c].type, normals[i][axis]);
    }
  }
  const PointCloud cloud = file.cloud();
  for (std::size_t i = 0; i < normals.size(); ++i) {
    EXPECT_EQ(cloud.normals[i][0], static_cast<float>(normals[i][0]));
    EXPECT_EQ(cloud.normals[i][1], static_cast<float>(normals[i][1]));
    EXPECT_EQ(cloud.normals[i][2], normals[i][2]);
  }

  // Output in the source's own encoding (big-endian sources come out little-endian): every
  // byte but the normals' is the input's.
  const bool ascii = GetParam() == Encoding::ascii;
  write_point_file((dir / "out.ply").string(), file, WriteOptions{ascii});
  EXPECT_EQ(test::read_file(dir / "out.ply"),
            test::ply_text(expected, ascii ? Encoding::ascii : Encoding::little_endian));
}

TEST_P(EveryEncoding, SetNormalsAddsFloatNormalsWhenAbsent) {
  TempDir dir;
  PlyModel model;
  model.comments = {"comment no normals yet"};
  Element vertex;
  vertex.name = "vertex";
  vertex.columns = {
      {"double", "x", ""}, {"double", "y", ""}, {"double", "z", ""}, {"uchar", "red", ""}, {"int", "ids", "uchar"}};
  vertex.rows = {{"1", "2", "3", "10", "2", "5", "6"}, {"4", "5", "6", "20", "0"}};
  Element face;
  face.name = "face";
  face.columns = {{"int", "vertex_indices", "uchar"}};
  face.rows = {{"3", "0", "1", "0"}};
  model.elements = {vertex, face};
  test::write_file(dir / "in.ply", test::ply_text(model, GetParam()));
  PointFile file = read_point_file((dir / "in.ply").string());
  ASSERT_FALSE(file.has_normals());
  EXPECT_FALSE(file.cloud().has_normals());

  file.set_normals({{0, 0, 1}, {0.5, -0.25, 2}});
  EXPECT_TRUE(file.has_normals());

  PlyModel expected = model;
  Element& expected_vertex = expected.elements[0];
  expected_vertex.columns.push_back({"float", "nx", ""});
  expected_vertex.columns.push_back({"float", "ny", ""});
  expected_vertex.columns.push_back({"float", "nz", ""});
  for (const char* token : {"0", "0", "1"}) expected_vertex.rows[0].push_back(token);
  for (const char* token : {"0.5", "-0.25", "2"}) expected_vertex.rows[1].push_back(token);
  const bool ascii = GetParam() == Encoding::ascii;
  write_point_file((dir / "out.ply").string(), file, WriteOptions{ascii});
  EXPECT_EQ(test::read_file(dir / "out.ply"),
            test::ply_text(expected, ascii ? Encoding::ascii : Encoding::little_endian));

  const PointCloud cloud = read_point_file((dir / "out.ply").string()).cloud();
  ASSERT_TRUE(cloud.has_normals());
  EXPECT_EQ(cloud.normals[1], (Vec3{0.5, -0.25, 2}));
  EXPECT_EQ(cloud.positions[1], (Vec3{4, 5, 6}));
}

TEST_P(EveryEncoding, PclNormalNamesAreNormals) {
  TempDir dir;
  PlyModel model;
  Element vertex;
  vertex.name = "vertex";
  vertex.columns = {{"float", "x", ""},        {"float", "y", ""},        {"float", "z", ""},
                    {"float", "normal_x", ""}, {"float", "normal_y", ""}, {"float", "normal_z", ""},
                    {"float", "curvature", ""}};
  vertex.rows = {{"1", "2", "3", "0", "1", "0", "0.5"}, {"4", "5", "6", "0.6", "0", "0.8", "0"}};
  model.elements = {vertex};
  test::write_file(dir / "pcl.ply", test::ply_text(model, GetParam()));
  PointFile file = read_point_file((dir / "pcl.ply").string());
  ASSERT_TRUE(file.has_normals());
  const PointCloud cloud = file.cloud();
  EXPECT_EQ(cloud.normals[0], (Vec3{0, 1, 0}));
  EXPECT_EQ(cloud.normals[1], (Vec3{0.6f, 0, 0.8f}));

  // Replaced in place under the same names.
  file.set_normals({{1, 0, 0}, {0, 0, 1}});
  PlyModel expected = model;
  expected.elements[0].rows = {{"1", "2", "3", "1", "0", "0", "0.5"}, {"4", "5", "6", "0", "0", "1", "0"}};
  write_point_file((dir / "out.ply").string(), file, WriteOptions{true});
  EXPECT_EQ(test::read_file(dir / "out.ply"), test::ply_text(expected, Encoding::ascii));
}

INSTANTIATE_TEST_SUITE_P(PointFile, EveryEncoding,
                         ::testing::Values(Encoding::ascii, Encoding::little_endian, Encoding::big_endian),
                         [](const auto& info) { return encoding_name(info.param); });

}  // namespace
}  // namespace pnf
