// pnf::PointFile — lossless reading and writing of point files (.ply, .pcd, .xyz, .xyzn, .pwn).
//
// A PointFile keeps everything its file carried, so that writing it back reproduces the file:
// for PLY the whole header (format, version, comments, obj_info, every element and property
// with its declared type, in order) and the raw values of every element; for PCD (PCL's point
// cloud format) every field with its SIZE, TYPE and COUNT, WIDTH and HEIGHT, VIEWPOINT and the
// bits of every value. pnf reads positions, normals and radii out of it (cloud()) and puts
// improved normals back (set_normals()); all other data passes through unchanged.
//
// Invalid points (PCD and PLY). PCL marks the pixels of an organised cloud that saw nothing with
// NaN coordinates. In a PCD file such a row is an invalid point, not an error: it stays in the
// file in its place (WIDTH x HEIGHT intact), cloud() leaves it out (so no neighbourhood or
// estimate sees it), and set_normals() gives it NaN normals. size() counts every row;
// valid_count() and row_of_point() map the points of cloud() to rows. In a PLY file a vertex is
// an invalid point in the same way when x, y and z are all NaN (as PCL's PLY writer writes one)
// or when a coordinate is NaN and so is its normal (as pnf writes an invalid PCD point to PLY), so
// that such files read back; any other NaN coordinate or normal is an error naming the vertex.
// In text formats a NaN is always an error, and every row is a valid point.
//
// Points without normals (PCD and PLY). PCL's NormalEstimation leaves NaN normals on points
// with too few neighbours. A row with finite coordinates whose three normal components are all
// NaN is handled like an invalid point: it stays in its place, cloud() leaves it out (so no
// filter neighbourhood sees it), set_normals() writes NaN normals back into it, and
// without_normals() counts it. A normal that is only partly NaN, infinite or zero is still an
// error naming the vertex. With ReadOptions::check_normals false such rows are ordinary valid
// points (for a caller that replaces every normal, as `pnf estimate` does).
//
// Thread safety: read_point_file and write_point_file may run concurrently on different paths.
// A PointFile is a plain value: const members may be called from several threads at once,
// set_normals needs exclusive access.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
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
  pcd,   // .pcd: PCL's Point Cloud Data, v0.7 (read and write) or v0.6 (read)
};

// The format a path's extension names (case-insensitive), as read_point_file and
// write_point_file choose it. Throws Error(invalid_argument) naming the path and the extension
// for any other.
PointFileFormat point_file_format(const std::string& path);

// The body encoding named on a PCD header's DATA line.
enum class PcdData { ascii, binary, binary_compressed };

// The encoding's name as a PCD header spells it ("ascii", "binary", "binary_compressed").
const char* to_string(PcdData data);

// The PLY and PCD header models (pnf/point_file_header.hpp), for header() and pcd_header().
struct PlyHeader;
struct PlyProperty;
struct PcdHeader;

// Options for read_point_file.
struct ReadOptions {
  // False: the file's normals are not checked (NaN, infinite or zero ones are read as they are),
  // for a caller that replaces them all, as `pnf estimate` does: PCL's NormalEstimation leaves
  // NaN normals where a point had too few neighbours. cloud() then returns them unchecked.
  bool check_normals = true;
};

// Options for write_point_file.
struct WriteOptions {
  // PLY only: write the ascii encoding instead of binary_little_endian. Ignored for text
  // formats, which are always text.
  bool ascii = false;
  // PCD only: the DATA encoding to write. Unset: the source's DATA for a file read from PCD
  // (a binary_compressed input stays binary_compressed), binary for anything else; with
  // `ascii` set and this unset, ascii.
  std::optional<PcdData> pcd_data;
};

// Throws Error(invalid_argument) naming `path` when `options` ask its format for what it does not
// have: a PCD DATA encoding (pcd_data) for a file that is not .pcd, which write_point_file
// ignores; a command given it (--pcd-data) says so before any work instead.
void check_write_options(const std::string& path, const WriteOptions& options);

// The contents of one point file. Always holds a "vertex" element with scalar x, y, z
// properties, and every valid point has finite coordinates and finite, non-zero normals
// (checked on read, unless ReadOptions::check_normals is false, and by set_normals). For a PCD
// file the vertex element has one property per value of each field (a field of COUNT k > 1
// gives name_0 ... name_{k-1}), and rows with a NaN coordinate are invalid (see the top of this
// header).
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
  // Elements, properties, types and counts, e.g. for `pnf info`. For a PCD file, the
  // equivalent PLY header: one "vertex" element of POINTS rows.
  const PlyHeader& header() const;
  // The PCD header of a file read from PCD (with normal fields added by set_normals), else
  // nullptr.
  const PcdHeader* pcd_header() const;
  // Number of rows N (vertices; for PCD every point, valid or not).
  std::size_t size() const;
  // Number of valid points M <= N: the size of cloud(). M == N except for invalid points (rows
  // with a NaN coordinate) and points without normals (see the top of this header).
  std::size_t valid_count() const;
  // Number of rows N - M left out of cloud() because their coordinates are finite but their
  // normal is NaN (points without normals, see the top of this header); 0 for a file read with
  // ReadOptions::check_normals false. The other N - M - without_normals() rows have a NaN
  // coordinate.
  std::size_t without_normals() const;
  // The row (0 .. N-1) of valid point i (0 .. M-1), in ascending order; i itself when every row
  // is valid. Throws invalid_argument when i >= M.
  std::size_t row_of_point(std::size_t i) const;

  // Positions (M), normals (M, or empty without normals) and radii (M, or empty without a
  // scalar "radius" vertex property) of the valid points in row order, converted exactly to
  // double (64-bit integer PCD fields are rounded to nearest).
  PointCloud cloud() const;
  // True when the vertex element has nx ny nz (or PCL's normal_x normal_y normal_z).
  bool has_normals() const;
  // The first of the normal properties declared with an integer type (their name and type:
  // header()), which set_normals refuses; nullptr when there are none or all are real.
  const PlyProperty* integer_normal_property() const;
  // Replaces the normals, stored in their declared type (float stays float, rounded to
  // nearest). When the file had none, appends nx ny nz properties to the vertex element:
  // float for a PLY file, double for a text file (whose values are all double); for PCD, float
  // fields normal_x normal_y normal_z after the last field. `normals` is M long (one per valid
  // point, in the order of cloud()), each finite and non-zero; it need not be unit length.
  // Invalid rows and points without normals get NaN normals. Throws invalid_argument naming
  // the index of a bad normal or the wrong size, and invalid_input when the file's normal
  // properties have an integer type.
  void set_normals(const std::vector<Vec3>& normals);
  // True when the vertex element has a scalar (not list) property `name`; for PCD, a field of
  // COUNT 1 (e.g. PCL's "curvature").
  bool has_scalar_property(const std::string& name) const;
  // Replaces the values of the scalar vertex property `name` (not a coordinate or a normal
  // component) with `values`: M of them, one per valid point in the order of cloud(), stored in
  // the property's declared floating-point type (rounded to nearest for float). Invalid rows and
  // points without normals get NaN, as PCL gives them. Throws invalid_argument when there is no
  // such property, it is a coordinate or normal component, or `values` is not M long, and
  // invalid_input when the property has an integer type.
  void set_scalar_property(const std::string& name, const std::vector<double>& values);

  // The values of element `element` (index into header().elements) in the PLY
  // binary_little_endian body layout: rows back to back, each property in its declared type,
  // a list as its count then its items. Throws invalid_argument for a bad index.
  const std::vector<unsigned char>& element_values(std::size_t element) const;

  struct Impl;  // internal; defined in lib/src/io

 private:
  explicit PointFile(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;

  friend PointFile read_point_file(const std::string& path, const ReadOptions& options);
  friend void write_point_file(const std::string& path, const PointFile& file, const WriteOptions& options);
};

// Reads the point file at `path` (`options`: ReadOptions); the format follows the extension (.ply, .pcd, .xyz, .xyzn,
// .pwn, case-insensitive). PCD: DATA ascii, binary (little-endian, as PCL writes it on every
// common host) or binary_compressed (LZF), any fields in any order. Throws invalid_argument
// for another extension, io when the file cannot be opened or read, and invalid_input for
// malformed contents, with one line that names the file, the element (PLY) or field (PCD), the
// line (ascii) or row index (binary) or point (PCD), and what is wrong.
PointFile read_point_file(const std::string& path, const ReadOptions& options = {});

// Writes `file` to `path` in the format its extension names. A PLY file keeps every element,
// property, comment and value of `file`; a file that came from PLY and is written in its
// original encoding (ascii, or binary_little_endian) reproduces every value it did not change
// byte for byte. A PCD file keeps every field (type, size, count, order), WIDTH, HEIGHT,
// VIEWPOINT and comments, and the bits of every value; in DATA ascii each value is written as
// the shortest text that reads back to it, except that PCL's convention is followed for an F 4
// field named rgb (written as TYPE U, its bits as an unsigned integer: packed colours are often
// NaN as floats) and padding fields "_" are left out; binary_compressed leaves the padding's bytes
// out as PCL does (they read back as zero). A PLY or text file written as PCD becomes one
// unorganised cloud of its vertices' scalar properties (nx ny nz named normal_x normal_y
// normal_z); list properties cannot be written to PCD. A PCD file written as PLY keeps its rows,
// invalid ones and points without normals included (they read back as such); a 64-bit integer
// field cannot be written to PLY. Text formats carry x y z [nx ny nz] of the valid points only
// (cloud()), 17 significant digits; .xyzn and .pwn need normals.
// The data goes to a temporary file in the target's folder that is renamed over `path`, so
// `path` is either replaced whole or left alone; on failure no temporary file remains. Throws
// invalid_argument for an unknown extension, a text format that needs normals the file lacks,
// a list to PCD or a 64-bit integer to PLY, and io (naming the path and the OS reason) when
// writing fails.
void write_point_file(const std::string& path, const PointFile& file, const WriteOptions& options = {});

}  // namespace pnf
