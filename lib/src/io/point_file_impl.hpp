// PointFile::Impl — what a PointFile stores, shared by the readers, the writers and PointFile.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "pnf/point_file.hpp"
#include "pnf/point_file_header.hpp"

namespace pnf {

// Indices of the vertex properties pnf uses, kNone where absent.
struct VertexFields {
  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  std::size_t x = kNone, y = kNone, z = kNone;
  std::size_t nx = kNone, ny = kNone, nz = kNone;
  std::size_t radius = kNone;
  bool has_normals() const { return nx != kNone; }
};

struct PointFile::Impl {
  PointFileFormat source_format = PointFileFormat::ply;
  PlyHeader header;
  // Parallel to header.elements: each element's values in the binary_little_endian layout
  // (see PointFile::element_values).
  std::vector<std::vector<unsigned char>> values;
  // For a file read from ascii PLY: parallel to header.elements, each element's original
  // tokens, one line per row, tokens separated by one space, every line ending in '\n'. Kept so
  // that ascii output repeats every unchanged value's text exactly; empty for other sources.
  std::vector<std::string> ascii_rows;
  std::size_t vertex_element = 0;  // index of "vertex" in header.elements
  VertexFields fields;             // found in header.elements[vertex_element]
  // The type set_normals gives normals it adds: float for PLY files, as is usual there; double
  // where every other value is double (text files, files built from a PointCloud).
  PlyScalar added_normal_type = PlyScalar::float32;
  // For a file read from PCD: its header, whose fields give the vertex properties in order
  // (one per value), kept in step with them by set_normals.
  PcdHeader pcd;
  // True when some rows are invalid points (check_vertices' InvalidRows) or points without
  // normals; then valid_rows lists the valid ones in ascending order. False: every row is valid,
  // valid_rows is empty.
  bool has_invalid_rows = false;
  std::vector<std::size_t> valid_rows;
  // How many of the rows left out of valid_rows have finite coordinates and a NaN normal
  // (PointFile::without_normals); the others have a NaN coordinate.
  std::size_t rows_without_normals = 0;
};

// Finds the "vertex" element and the properties pnf uses, and stores them in `impl`. Throws
// invalid_input (message prefixed with `path`) when the element or x/y/z is missing, when only
// some normal components are present, or when a used property is a list.
void locate_vertex_fields(PointFile::Impl& impl, const std::string& path);

// Which rows are invalid points rather than errors: kept, passed through and not filtered.
enum class InvalidRows {
  none,  // every NaN is an error (text files, distributed PLY slices)
  // PLY: x, y and z all NaN (PCL's PLY writer's invalid point), or a NaN coordinate with a NaN
  // normal (pnf's, for an invalid PCD point written as PLY); a NaN anywhere else is an error
  nan_point,
  any_nan_coordinate,  // PCD: a NaN coordinate, PCL's mark of an invalid point
};

// Checks that every position and normal is finite and every normal non-zero. `row_lines`
// gives, for an ascii source, the file line of each vertex row (empty otherwise) so that the
// message can name it. Throws invalid_input naming `path`, the vertex index and the line.
// A row that `invalid` marks is an invalid point instead: it is not checked further, and
// impl.has_invalid_rows / impl.valid_rows record it; for PCD, messages say "point" rather than
// "vertex". Where `invalid` is not none and check_normals is true, a row with finite coordinates
// whose three normal components are all NaN (PCL's NormalEstimation's mark of a point with too
// few neighbours) is left out in the same way and counted in impl.rows_without_normals; a normal
// only partly NaN, infinite or zero stays an error.
// With check_normals false (ReadOptions), the normals are left unchecked.
void check_vertices(PointFile::Impl& impl, const std::string& path, const std::vector<std::size_t>& row_lines,
                    InvalidRows invalid = InvalidRows::none, bool check_normals = true);

}  // namespace pnf
