// Round trips of real scans from ../shared/data: Armadillo.ply (ascii, 38,294 vertices with
// normals) and bunny_scans/bun000.ply (ascii, vertices and a range_grid list element).
// Skipped when the data folder is absent.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "ply_test_files.hpp"
#include "pnf/point_file.hpp"
#include "pnf/point_file_header.hpp"

namespace pnf {
namespace {

// PNF_SHARED_DATA wins over the folder the build names (PNF_SHARED_DATA_DIR).
std::filesystem::path shared_data_dir() {
  if (const char* from_environment = std::getenv("PNF_SHARED_DATA")) return from_environment;
#ifdef PNF_SHARED_DATA_DIR
  return PNF_SHARED_DATA_DIR;
#else
  return {};
#endif
}

// The body of an ascii PLY with each line's tokens joined by one space, as pnf writes them.
std::string normalised_ascii_body(const std::string& file) {
  const std::size_t body = file.find("end_header\n");
  std::string out;
  std::size_t at = body + std::string("end_header\n").size();
  while (at < file.size()) {
    std::size_t end = file.find('\n', at);
    if (end == std::string::npos) end = file.size();
    std::string line;
    std::size_t i = at;
    while (i < end) {
      while (i < end && (file[i] == ' ' || file[i] == '\t' || file[i] == '\r')) ++i;
      const std::size_t begin = i;
      while (i < end && file[i] != ' ' && file[i] != '\t' && file[i] != '\r') ++i;
      if (i > begin) line += (line.empty() ? "" : " ") + file.substr(begin, i - begin);
    }
    if (!line.empty()) out += line + '\n';
    at = end + 1;
  }
  return out;
}

void expect_same_file(const PointFile& actual, const PointFile& expected) {
  const PlyHeader& a = actual.header();
  const PlyHeader& b = expected.header();
  ASSERT_EQ(a.elements.size(), b.elements.size());
  for (std::size_t e = 0; e < b.elements.size(); ++e) {
    EXPECT_EQ(a.elements[e].name, b.elements[e].name);
    EXPECT_EQ(a.elements[e].count, b.elements[e].count);
    ASSERT_EQ(a.elements[e].properties.size(), b.elements[e].properties.size());
    for (std::size_t p = 0; p < b.elements[e].properties.size(); ++p) {
      const PlyProperty& x = a.elements[e].properties[p];
      const PlyProperty& y = b.elements[e].properties[p];
      EXPECT_EQ(x.name, y.name);
      EXPECT_EQ(x.type_name, y.type_name);
      EXPECT_EQ(x.is_list, y.is_list);
      EXPECT_EQ(x.count_type_name, y.count_type_name);
    }
    EXPECT_TRUE(actual.element_values(e) == expected.element_values(e))
        << "element " << b.elements[e].name << " differs";
  }
  ASSERT_EQ(a.comments.size(), b.comments.size());
  for (std::size_t i = 0; i < b.comments.size(); ++i) {
    EXPECT_EQ(a.comments[i].keyword, b.comments[i].keyword);
    EXPECT_EQ(a.comments[i].text, b.comments[i].text);
    EXPECT_EQ(a.comments[i].position, b.comments[i].position);
  }
  const PointCloud x = actual.cloud();
  const PointCloud y = expected.cloud();
  EXPECT_TRUE(x.positions == y.positions);
  EXPECT_TRUE(x.normals == y.normals);
}

class SharedData : public ::testing::TestWithParam<const char*> {};

TEST_P(SharedData, RoundTripsInAsciiAndBinary) {
  const std::filesystem::path source = shared_data_dir() / GetParam();
  if (shared_data_dir().empty() || !std::filesystem::exists(source)) {
    GTEST_SKIP() << "shared data file " << source
                 << " not found; set PNF_SHARED_DATA to the folder holding Armadillo.ply";
  }
  const PointFile original = read_point_file(source.string());
  const std::string name = GetParam();
  if (name == "Armadillo.ply") {
    EXPECT_EQ(original.size(), 38294u);
    EXPECT_TRUE(original.has_normals());
  } else {
    ASSERT_EQ(original.header().elements.size(), 2u);
    EXPECT_EQ(original.header().elements[1].name, "range_grid");
    EXPECT_EQ(original.header().elements[1].count, 204800u);
    EXPECT_FALSE(original.has_normals());
  }

  test::TempDir dir;
  write_point_file((dir / "ascii.ply").string(), original, WriteOptions{true});
  write_point_file((dir / "binary.ply").string(), original, WriteOptions{false});
  // Ascii output repeats every token of the source; only spacing may differ.
  EXPECT_TRUE(normalised_ascii_body(test::read_file(dir / "ascii.ply")) ==
              normalised_ascii_body(test::read_file(source)))
      << "ascii body differs from " << source;

  const PointFile ascii = read_point_file((dir / "ascii.ply").string());
  const PointFile binary = read_point_file((dir / "binary.ply").string());
  EXPECT_EQ(binary.header().encoding, PlyEncoding::binary_little_endian);
  expect_same_file(ascii, original);
  expect_same_file(binary, original);

  // Binary to ascii and back reproduces the binary file byte for byte.
  write_point_file((dir / "ascii_from_binary.ply").string(), binary, WriteOptions{true});
  write_point_file((dir / "binary_again.ply").string(), read_point_file((dir / "ascii_from_binary.ply").string()),
                   WriteOptions{});
  EXPECT_TRUE(test::read_file(dir / "binary_again.ply") == test::read_file(dir / "binary.ply"));
}

INSTANTIATE_TEST_SUITE_P(PointFile, SharedData, ::testing::Values("Armadillo.ply", "bunny_scans/bun000.ply"),
                         [](const auto& info) { return std::string(info.index == 0 ? "Armadillo" : "bun000"); });

}  // namespace
}  // namespace pnf
