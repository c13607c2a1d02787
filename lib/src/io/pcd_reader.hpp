// Reading PCD files (DATA ascii, binary, binary_compressed) into a PointFile::Impl.
#pragma once

#include <memory>
#include <string>

#include "point_file_impl.hpp"

namespace pnf {

// Reads the PCD file at `path`: header, then every point's values in the binary layout (rows
// of the fields' bytes, padding included; values little-endian); then checks the points, rows
// with a NaN coordinate being invalid points. Every count is checked against the bytes left in
// the file before anything is allocated from it. Throws io when the file cannot be read and
// invalid_input, naming the file, the header line, field, line or point, when it is malformed.
std::unique_ptr<PointFile::Impl> read_pcd(const std::string& path, const ReadOptions& options = {});

}  // namespace pnf
