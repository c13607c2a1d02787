// Errors reading PCD files: each is invalid_input, one line, names the file and the place
// (header line and field, line and point, the compressed block) and says what is wrong; and
// counts are checked against the file before they allocate anything.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "pcd_test_files.hpp"
#include "ply_test_files.hpp"
#include "pnf/error.hpp"
#include "pnf/point_file.hpp"

namespace pnf {
namespace {

using test::TempDir;
using test::TestField;

const std::vector<TestField> kXyz = {{"x", 'F', 4, 1}, {"y", 'F', 4, 1}, {"z", 'F', 4, 1}};

std::string header_lines(const std::string& fields_to_data) {
  return "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n" + fields_to_data;
}

std::string xyz_rows(int points) {
  std::string rows;
  for (int p = 0; p < points; ++p) {
    rows += test::float_bytes(float(p)) + test::float_bytes(1) + test::float_bytes(2);
  }
  return rows;
}

void expect_pcd_error(const std::string& name, const std::string& contents, const std::vector<std::string>& parts) {
  TempDir dir;
  test::write_file(dir / name, contents);
  const std::string path = (dir / name).string();
  try {
    read_point_file(path);
    ADD_FAILURE() << name << ": expected an error containing '" << parts.at(0) << "'";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_EQ(error.code(), ErrorCode::invalid_input) << message;
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    for (const std::string& part : parts) {
      EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
    }
    EXPECT_EQ(message.find('\n'), std::string::npos) << "not one line: " << message;
  }
}

TEST(PcdErrors, HeaderCountsThatDisagree) {
  std::string points = test::test_pcd_header(kXyz, 2, 2, "binary");
  points.replace(points.find("POINTS 4"), 8, "POINTS 5");
  expect_pcd_error("points.pcd", points + xyz_rows(5), {"POINTS 5 disagrees with WIDTH 2 x HEIGHT 2 = 4"});
  expect_pcd_error("size.pcd", header_lines("FIELDS x y z\nSIZE 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nDATA ascii\n"),
                   {"header line 4", "SIZE has 2 entries but FIELDS names 3 fields"});
  expect_pcd_error("type.pcd", header_lines("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F F\nWIDTH 1\nDATA ascii\n"),
                   {"header line 5", "TYPE has 4 entries but FIELDS names 3"});
  expect_pcd_error("count.pcd", header_lines("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1\nWIDTH 1\nDATA ascii\n"),
                   {"header line 6", "COUNT has 2 entries"});
  expect_pcd_error("before.pcd", header_lines("SIZE 4 4 4\nFIELDS x y z\nDATA ascii\n"), {"SIZE before FIELDS"});
  expect_pcd_error("height.pcd", header_lines("FIELDS x y z\nHEIGHT 3\nPOINTS 3\nDATA ascii\n"),
                   {"HEIGHT 3 without WIDTH"});
  expect_pcd_error("twice.pcd", header_lines("FIELDS x y z\nWIDTH 1\nWIDTH 2\nDATA ascii\n"),
                   {"header line 5", "a second WIDTH line"});
}

TEST(PcdErrors, FieldsThatAreNotPcd) {
  expect_pcd_error("letter.pcd", header_lines("FIELDS x y z\nSIZE 4 4 4\nTYPE F X F\nWIDTH 1\nDATA ascii\n"),
                   {"header line 5", "TYPE of field 'y' is 'X' (expected I, U or F)"});
  expect_pcd_error("half.pcd", header_lines("FIELDS x y z\nSIZE 4 4 2\nTYPE F F F\nWIDTH 1\nDATA ascii\n"),
                   {"field 'z' has TYPE F with SIZE 2, not a PCD type"});
  expect_pcd_error("size3.pcd", header_lines("FIELDS x y z\nSIZE 4 3 4\nWIDTH 1\nDATA ascii\n"),
                   {"SIZE of field 'y' is 3 (expected 1, 2, 4 or 8)"});
  expect_pcd_error("noz.pcd", header_lines("FIELDS x y\nWIDTH 1\nDATA ascii\n"), {"no field 'z'"});
  expect_pcd_error("xcount.pcd", header_lines("FIELDS x y z\nCOUNT 2 1 1\nWIDTH 1\nDATA ascii\n"),
                   {"field 'x' has COUNT 2 (expected 1)"});
  expect_pcd_error("dup.pcd", header_lines("FIELDS x y z y\nWIDTH 1\nDATA ascii\n"), {"a second field 'y'"});
  expect_pcd_error("zero.pcd", header_lines("FIELDS x y z\nCOUNT 1 0 1\nWIDTH 1\nDATA ascii\n"),
                   {"COUNT of field 'y' is 0"});
  expect_pcd_error("data.pcd", header_lines("FIELDS x y z\nWIDTH 1\nDATA binary_lz4\n"),
                   {"header line 5", "unknown DATA 'binary_lz4'"});
  expect_pcd_error("keyword.pcd", header_lines("FIELDS x y z\nDEPTH 1\nDATA ascii\n"),
                   {"header line 4", "unknown keyword 'DEPTH'"});
  expect_pcd_error("nodata.pcd", header_lines("FIELDS x y z\nWIDTH 1\n"), {"the header has no DATA line"});
  // The body right after the header's last line: named as a missing DATA line, binary bytes
  // (starting with a NUL here) never quoted.
  const std::string no_data = header_lines("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 3\nPOINTS 3\n");
  for (const auto& [name, body] :
       std::vector<std::pair<std::string, std::string>>{{"binary_body.pcd", xyz_rows(3)},
                                                        {"ascii_body.pcd", "0 1 2\n1 1 2\n2 1 2\n"},
                                                        {"nan_body.pcd", "nan nan nan\n1 1 2\n2 1 2\n"}}) {
    SCOPED_TRACE(name);
    expect_pcd_error(name, no_data + body, {"header line 9: point data where a header line should be", "no DATA line"});
  }
  expect_pcd_error("viewpoint.pcd", header_lines("FIELDS x y z\nWIDTH 1\nVIEWPOINT 0 0 0 1 0 0\nDATA ascii\n"),
                   {"VIEWPOINT has 6 values (expected 7"});
  expect_pcd_error("empty.pcd", "", {"not a PCD file: the file is empty"});
}

TEST(PcdErrors, TruncatedAndOverlongData) {
  const std::string header = test::test_pcd_header(kXyz, 4, 1, "binary");
  expect_pcd_error("short.pcd", header + xyz_rows(4).substr(0, 30),
                   {"point 2", "the file ends inside this point", "4 points of 12 bytes", "only 30 bytes"});
  expect_pcd_error("long.pcd", header + xyz_rows(5), {"12 bytes of data after the last of 4 points"});
  const std::string ascii = test::test_pcd_header(kXyz, 3, 1, "ascii");
  expect_pcd_error("ashort.pcd", ascii + "1 2 3\n", {"the header declares 3 points of 3 values, but only 6 bytes"});
  expect_pcd_error("aends.pcd", ascii + "1 2 3\n4 5 6\n\n\n\n\n\n\n\n", {"the file ends after 2 of 3 points"});
  expect_pcd_error("atokens.pcd", ascii + "1 2 3\n4 5      \n7 8 9\n",
                   {"line 13, point 1", "expected 3 values (the fields' COUNT), found 2"});
  expect_pcd_error("atoken.pcd", ascii + "1 2 3\n4 five 6\n7 8 9\n",
                   {"line 13, point 1, field 'y'", "'five' is not a number for TYPE F SIZE 4"});
  expect_pcd_error("amore.pcd", ascii + "1 2 3\n4 5 6\n7 8 9\n1 1 1\n", {"line 15", "data after the last of 3 points"});
  const std::vector<TestField> with_u8 = {{"x", 'F', 4, 1}, {"y", 'F', 4, 1}, {"z", 'F', 4, 1}, {"label", 'U', 1, 1}};
  expect_pcd_error("range.pcd", test::test_pcd_header(with_u8, 1, 1, "ascii") + "1 2 3 256\n",
                   {"field 'label'", "'256' is out of range for TYPE U SIZE 1"});
}

TEST(PcdErrors, AbsurdCountsAreRefusedBeforeAllocating) {
  // 10^15 points would be 12 PB: refused from the file size, not by a failed allocation.
  expect_pcd_error("huge.pcd",
                   header_lines("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1000000000000000\n"
                                "HEIGHT 1\nPOINTS 1000000000000000\nDATA binary\n") +
                       xyz_rows(2),
                   {"point 2", "1000000000000000 points of 12 bytes but only 24 bytes follow DATA"});
  expect_pcd_error("hugea.pcd", header_lines("FIELDS x y z\nWIDTH 1000000000000000\nDATA ascii\n") + "1 2 3\n",
                   {"1000000000000000 points of 3 values, but only 6 bytes of text follow DATA"});
  expect_pcd_error("hugec.pcd",
                   header_lines("FIELDS x y z\nWIDTH 1000000000000000\nDATA binary_compressed\n") + test::u32_le(4) +
                       test::u32_le(12) + "abcd",
                   {"more than the 4 GiB"});
  expect_pcd_error("count.pcd", header_lines("FIELDS x y z f\nCOUNT 1 1 1 4000000000\nWIDTH 1\nDATA ascii\n"),
                   {"COUNT of field 'f' is 4000000000 (expected 1 to 65536)"});
  expect_pcd_error("overflow.pcd", header_lines("FIELDS x y z\nWIDTH 4294967296\nHEIGHT 4294967296\nDATA ascii\n"),
                   {"disagrees with WIDTH 4294967296 x HEIGHT 4294967296"});
}

TEST(PcdErrors, CompressedBlocksThatDoNotDecompressToTheDeclaredSize) {
  const std::string header = test::test_pcd_header(kXyz, 2, 1, "binary_compressed");
  const std::string good = test::test_compressed_body(kXyz, xyz_rows(2));
  const std::string lzf = good.substr(8);
  expect_pcd_error("prefix.pcd", header + "abc", {"the file ends inside the 8-byte size prefix"});
  expect_pcd_error("declared.pcd", header + test::u32_le(lzf.size()) + test::u32_le(20) + lzf,
                   {"declares 20 uncompressed bytes, but the header declares 2 points of 12 bytes", "24 in all"});
  expect_pcd_error("cut.pcd", header + good.substr(0, good.size() - 5),
                   {"the compressed block declares " + std::to_string(lzf.size()) + " bytes but only"});
  // A stream that decodes to fewer bytes than declared, one that decodes to more, and garbage
  // (a back reference before the start of the output).
  const std::string fewer = test::lzf_literals(xyz_rows(2).substr(0, 20));
  expect_pcd_error("fewer.pcd", header + test::u32_le(fewer.size()) + test::u32_le(24) + fewer,
                   {"the compressed block", "not the declared 24 bytes"});
  const std::string more = test::lzf_literals(xyz_rows(3));
  expect_pcd_error("more.pcd", header + test::u32_le(more.size()) + test::u32_le(24) + more,
                   {"decompresses to more than the declared 24 bytes"});
  const std::string garbage = "\x20\x05";  // copy 3 bytes from 6 before the start
  expect_pcd_error("garbage.pcd", header + test::u32_le(garbage.size()) + test::u32_le(24) + garbage,
                   {"is not valid LZF data"});
  expect_pcd_error(
      "ratio.pcd",
      test::test_pcd_header(kXyz, 1000, 1, "binary_compressed") + test::u32_le(4) + test::u32_le(12000) + "abcd",
      {"the compressed block of 4 bytes cannot hold the declared 12000 bytes"});
}

TEST(PcdErrors, BadValuesNameThePoint) {
  const std::vector<TestField> fields = {{"x", 'F', 4, 1},        {"y", 'F', 4, 1},        {"z", 'F', 4, 1},
                                         {"normal_x", 'F', 4, 1}, {"normal_y", 'F', 4, 1}, {"normal_z", 'F', 4, 1}};
  const std::string header = test::test_pcd_header(fields, 3, 1, "ascii");
  expect_pcd_error("inf.pcd", header + "0 0 0 0 0 1\n0 inf 0 0 0 1\nnan nan nan nan nan nan\n",
                   {"line 13, point 1: coordinate y is +infinity"});
  expect_pcd_error("normal.pcd", header + "nan 0 0 nan nan nan\n0 0 0 0 0 0\n0 0 0 0 0 1\n",
                   {"point 1: the normal is zero-length"});
  expect_pcd_error("nannormal.pcd", header + "0 0 0 0 0 1\n0 0 0 nan 0 1\n0 0 0 0 0 1\n",
                   {"point 1: normal component normal_x is NaN"});
}

}  // namespace
}  // namespace pnf
