// Reading PLY files (ascii, binary_little_endian, binary_big_endian) into a PointFile::Impl.
#pragma once

#include <memory>
#include <string>

#include "point_file_impl.hpp"

namespace pnf {

// Reads the PLY file at `path`: header, every element's values and, for ascii, every token's
// text; then checks the vertices. Throws io when the file cannot be read and invalid_input,
// naming the file, the element and the line (ascii) or row (binary), when it is malformed.
std::unique_ptr<PointFile::Impl> read_ply(const std::string& path, const ReadOptions& options = {});

}  // namespace pnf
