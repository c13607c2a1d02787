// Writing a PointFile::Impl as PLY (ascii or binary_little_endian).
#pragma once

#include <string>

#include "atomic_file.hpp"
#include "point_file_impl.hpp"

namespace pnf {

// The header write_ply writes for `header` (its comments in their places), ending in
// "end_header\n". The distributed writer (lib/src/mpi) writes the same.
std::string header_text(const PlyHeader& header, bool ascii);

// Writes the header (comments in their places) and every element of `impl` to `out`. Binary
// output copies the stored values unchanged; ascii output repeats the stored tokens of an
// ascii source and otherwise formats each value exactly in its type.
void write_ply(const PointFile::Impl& impl, bool ascii, AtomicFile& out);

}  // namespace pnf
