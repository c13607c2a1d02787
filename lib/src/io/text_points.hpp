// Reading and writing the text point formats: .xyz (x y z, or x y z nx ny nz), .xyzn and .pwn
// (x y z nx ny nz), one point per line.
#pragma once

#include <memory>
#include <string>

#include "atomic_file.hpp"
#include "point_file_impl.hpp"

namespace pnf {

// Reads the text point file at `path`. Blank lines and lines starting with '#' are skipped; a
// first data line holding one integer (the point count some CGAL writers put there) is skipped
// too. For .xyz the first point line decides between 3 and 6 values per line. The result has a
// "vertex" element with double x y z [nx ny nz]. Throws io when the file cannot be read and
// invalid_input naming the file and line for a wrong number of values, a token that is not a
// number, a non-finite value or a zero normal.
std::unique_ptr<PointFile::Impl> read_text_points(const std::string& path, PointFileFormat format,
                                                  const ReadOptions& options = {});

// Writes the positions, and normals when `cloud` has them, one point per line with 17
// significant digits so that every double reads back exactly. The caller checks that a format
// needing normals gets them.
void write_text_points(const PointCloud& cloud, AtomicFile& out);

}  // namespace pnf
