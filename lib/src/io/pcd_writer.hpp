// Writing a PointFile::Impl as PCD v0.7 (DATA ascii, binary or binary_compressed).
#pragma once

#include "atomic_file.hpp"
#include "point_file_impl.hpp"

namespace pnf {

// Writes `impl` to `out` as PCD with DATA `data`. A file read from PCD keeps its header (fields,
// WIDTH, HEIGHT, VIEWPOINT, comments) and every value's bits; any other file becomes an
// unorganised cloud of its vertex element's scalar properties (nx ny nz as normal_x normal_y
// normal_z). Throws invalid_argument naming `path` when a vertex property is a list (PCD has
// none) or binary_compressed data would pass its 4 GiB limit.
void write_pcd(const PointFile::Impl& impl, PcdData data, const std::string& path, AtomicFile& out);

}  // namespace pnf
