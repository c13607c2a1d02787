// The header models of pnf::PointFile (pnf/point_file.hpp): PointFile::header() describes any
// file as the PLY header pnf would write for it, PointFile::pcd_header() a PCD file's own header.
// For callers that look at a file's elements, properties and types (e.g. `pnf info`); reading
// and writing points needs only pnf/point_file.hpp.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "pnf/point_file.hpp"

namespace pnf {

// One field of a PCD header: a FIELDS name with its SIZE, TYPE and COUNT.
struct PcdField {
  std::string name;       // "_" is PCL's padding field: bytes that belong to no value
  char type = 'F';        // 'I' signed integer, 'U' unsigned integer, 'F' floating point
  unsigned size = 4;      // bytes per value: 1, 2, 4 or 8 for I and U; 4 or 8 for F
  std::size_t count = 1;  // values per point, at least 1
};

// A PCD header, in the order PCL writes it.
struct PcdHeader {
  std::vector<std::string> comments;  // the '#' lines, each whole and unchanged, in file order
  std::string version = "0.7";        // VERSION as read ("0.7", ".7", "0.6"); pnf writes 0.7
  std::vector<PcdField> fields;       // in file order
  std::size_t width = 0;              // points per row (organised) or all points (height 1)
  std::size_t height = 1;             // rows; 1 for an unorganised cloud
  // VIEWPOINT: the sensor's origin tx ty tz (model units) and orientation qw qx qy qz.
  std::array<double, 7> viewpoint = {0, 0, 0, 1, 0, 0, 0};
  std::size_t points = 0;          // POINTS = width * height
  PcdData data = PcdData::binary;  // DATA
};

// The body encoding named on a PLY header's format line.
enum class PlyEncoding { ascii, binary_little_endian, binary_big_endian };

// The encoding's name as a PLY header spells it ("ascii", "binary_little_endian", ...).
const char* to_string(PlyEncoding encoding);

// A PLY scalar type. Both spellings of the header ("char"/"int8", "float"/"float32", ...) map
// to the same value; PlyProperty keeps the spelling the file used.
// int64 and uint64 exist only for PCD fields (SIZE 8, TYPE I or U); PLY has no such type.
enum class PlyScalar { int8, uint8, int16, uint16, int32, uint32, float32, float64, int64, uint64 };

// One property line of a PLY header.
struct PlyProperty {
  std::string name;
  PlyScalar type = PlyScalar::float32;  // the value type; for a list, the type of its items
  std::string type_name;                // `type` as spelled in the header, written back as is
  bool is_list = false;
  PlyScalar count_type = PlyScalar::uint8;  // lists only: the type of the item count
  std::string count_type_name;              // lists only: `count_type` as spelled
};

// One element line of a PLY header with its properties, in header order.
struct PlyElement {
  std::string name;
  std::size_t count = 0;  // number of rows
  std::vector<PlyProperty> properties;
};

// A "comment" or "obj_info" header line.
struct PlyComment {
  std::string keyword;  // "comment" or "obj_info"
  std::string text;     // the rest of the line after the keyword and one separator, unchanged
  // Where the line stood: the number of format, element and property lines before it.
  std::size_t position = 0;
};

// A PLY header. For a text-format file this is the equivalent header pnf would write for it:
// ascii, one "vertex" element with double x y z and, when present, double nx ny nz.
struct PlyHeader {
  PlyEncoding encoding = PlyEncoding::ascii;
  std::string version = "1.0";
  std::vector<PlyComment> comments;  // in file order
  std::vector<PlyElement> elements;  // in file order
};

}  // namespace pnf
