// pnf::PointFile — lossless reading and writing of point files (.ply, .xyz, .xyzn, .pwn).
//
// A PointFile keeps everything its file carried, so that writing it back reproduces the file:
// for PLY the whole header (format, version, comments, obj_info, every element and property
// with its declared type, in order) and the raw values of every element. pnf reads positions,
// normals and radii out of it (cloud()) and puts improved normals back (set_normals()); all
// other data passes through unchanged.
//
// Thread safety: read_point_file and write_point_file may run concurrently on different paths.
// A PointFile is a plain value: const members may be called from several threads at once,
// set_normals needs exclusive access.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "pnf/point_cloud.hpp"

namespace pnf {

// Which kind of file a PointFile came from, chosen by extension (case-insensitive).
enum class PointFileFormat {
  ply,   // .ply: ascii, binary_little_endian or binary_big_endian
  xyz,   // .xyz: "x y z" or "x y z nx ny nz" per line
  xyzn,  // .xyzn: "x y z nx ny nz" per line
  pwn,   // .pwn: "x y z nx ny nz" per line
};

// The body encoding named on a PLY header's format line.
enum class PlyEncoding { ascii, binary_little_endian, binary_big_endian };

// The encoding's name as a PLY header spells it ("ascii", "binary_little_endian", ...).
const char* to_string(PlyEncoding encoding);

// A PLY scalar type. Both spellings of the header ("char"/"int8", "float"/"float32", ...) map
// to the same value; PlyProperty keeps the spelling the file used.
enum class PlyScalar { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

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

// Options for write_point_file.
struct WriteOptions {
  // PLY only: write the ascii encoding instead of binary_little_endian. Ignored for text
  // formats, which are always text.
  bool ascii = false;
};

// The contents of one point file. Always holds a "vertex" element with scalar x, y, z
// properties, and every vertex has finite coordinates and finite, non-zero normals (checked on
// read and by set_normals).
class PointFile {
 public:
  // An empty cloud: zero vertices.
  PointFile();
  // A file holding `cloud`: a "vertex" element with double x y z, then nx ny nz when the cloud
  // has normals, then radius when it has radii. Throws invalid_argument when normals or radii
  // are present but not of size N, or when a coordinate, normal or radius is not finite, or a
  // normal is zero.
  explicit PointFile(const PointCloud& cloud);
  PointFile(const PointFile& other);
  PointFile(PointFile&& other) noexcept;  // leaves `other` fit only to be assigned or destroyed
  PointFile& operator=(const PointFile& other);
  PointFile& operator=(PointFile&& other) noexcept;
  ~PointFile();

  // The format the file was read from; ply for a PointFile built from a PointCloud.
  PointFileFormat source_format() const;
  // Elements, properties, types and counts, e.g. for `pnf info`.
  const PlyHeader& header() const;
  // Number of vertices N.
  std::size_t size() const;

  // Positions (N), normals (N, or empty without normals) and radii (N, or empty without a
  // scalar "radius" vertex property), converted exactly to double.
  PointCloud cloud() const;
  // True when the vertex element has nx ny nz (or PCL's normal_x normal_y normal_z).
  bool has_normals() const;
  // Replaces the normals, stored in their declared type (float stays float, rounded to
  // nearest). When the file had none, appends nx ny nz properties to the vertex element:
  // float for a PLY file, double for a text file (whose values are all double). `normals` is
  // N long, each finite and non-zero; it need not be unit length. Throws invalid_argument
  // naming the index of a bad normal or the wrong size, and invalid_input when the file's
  // normal properties have an integer type.
  void set_normals(const std::vector<Vec3>& normals);

  // The values of element `element` (index into header().elements) in the PLY
  // binary_little_endian body layout: rows back to back, each property in its declared type,
  // a list as its count then its items. Throws invalid_argument for a bad index.
  const std::vector<unsigned char>& element_values(std::size_t element) const;

  struct Impl;  // internal; defined in lib/src/io

 private:
  explicit PointFile(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;

  friend PointFile read_point_file(const std::string& path);
  friend void write_point_file(const std::string& path, const PointFile& file, const WriteOptions& options);
};

// Reads the point file at `path`; the format follows the extension (.ply, .xyz, .xyzn, .pwn,
// case-insensitive). Throws invalid_argument for another extension, io when the file cannot be
// opened or read, and invalid_input for malformed contents, with one line that names the file,
// the element and the line (ascii) or row index (binary), and what is wrong.
PointFile read_point_file(const std::string& path);

// Writes `file` to `path` in the format its extension names. A PLY file keeps every element,
// property, comment and value of `file`; a file that came from PLY and is written in its
// original encoding (ascii, or binary_little_endian) reproduces every value it did not change
// byte for byte. Text formats carry x y z [nx ny nz], 17 significant digits; .xyzn and .pwn
// need normals. The data goes to a temporary file in the target's folder that is renamed over
// `path`, so `path` is either replaced whole or left alone; on failure no temporary file
// remains. Throws invalid_argument for an unknown extension or a text format that needs normals
// the file lacks, and io (naming the path and the OS reason) when writing fails.
void write_point_file(const std::string& path, const PointFile& file, const WriteOptions& options = {});

}  // namespace pnf
