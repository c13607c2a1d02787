// Parallel PLY I/O for a distributed run: each rank reads its own slice of the vertex rows of a
// binary_little_endian file (offsets from the header; no rank reads the whole file) and writes
// its slice of the result into one shared file in the run's staging folder beside the target
// (staged_output.hpp), which takes the target's name once every rank has succeeded. Files this
// cannot slice (ascii, big endian, list properties, integer normals) are left to the caller's
// rank-0 path.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

#include "pnf/point_cloud.hpp"
#include "pnf/point_file.hpp"
#include "pnf/point_file_header.hpp"

namespace pnf::mpi::detail {

// What every rank learns from the header (each rank reads the header itself).
struct PlySliceLayout {
  bool sliceable = false;  // false: use the rank-0 path; why_not says why
  std::string why_not;
  PlyHeader header;                 // as read_point_file reads it
  std::string output_header;        // the header write_point_file writes for it (binary_little_endian)
  std::uint64_t body_offset = 0;    // first byte after end_header
  std::uint64_t vertex_offset = 0;  // first byte of the vertex rows
  std::uint64_t vertex_count = 0;
  std::uint64_t row_size = 0;
  std::uint64_t body_end = 0;  // end of the last element's rows
  std::size_t position_offset[3] = {0, 0, 0}, normal_offset[3] = {0, 0, 0}, radius_offset = 0;
  PlyScalar position_type[3] = {}, normal_type[3] = {}, radius_type = PlyScalar::float32;
  bool has_normals = false, has_radius = false;
};

// Reads and parses the header of `path` (local, not collective). A file it cannot open or a
// header it cannot slice gives sliceable = false (the rank-0 path then reads the file and
// reports what is wrong as one process would).
PlySliceLayout read_slice_layout(const std::string& path);

// Rows [first, first + count) of the vertex element of rank `rank` of `ranks`.
void slice_rows(const PlySliceLayout& layout, int rank, int ranks, std::uint64_t& first, std::uint64_t& count);

// This rank's slice: its rows' raw bytes, and their positions, normals and radii as double.
struct PlySlice {
  std::uint64_t first = 0;
  std::vector<unsigned char> rows;
  PointCloud cloud;
};

// Reads this rank's rows (local). Throws io naming the file and the rows when they cannot be
// read (a truncated file, say).
PlySlice read_slice(const std::string& path, const PlySliceLayout& layout, int rank, int ranks);

// Collective: writes the header, the other elements (copied from `in_path`) and every rank's
// rows, with `normals` (the slice's rows) stored in their declared types, into `path`, a new
// file that rank 0 creates (in the run's staging folder: StagedOutput); every rank writes its
// rows and syncs. On any rank's failure every rank throws the agreed error; removing `path` is
// the caller's.
void write_slices(MPI_Comm comm, const std::string& in_path, const std::string& path, const PlySliceLayout& layout,
                  PlySlice& slice, const std::vector<Vec3>& normals);

}  // namespace pnf::mpi::detail
