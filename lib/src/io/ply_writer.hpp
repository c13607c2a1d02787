// Writing a PointFile::Impl as PLY (ascii or binary_little_endian).
#pragma once

#include "atomic_file.hpp"
#include "point_file_impl.hpp"

namespace pnf {

// Writes the header (comments in their places) and every element of `impl` to `out`. Binary
// output copies the stored values unchanged; ascii output repeats the stored tokens of an
// ascii source and otherwise formats each value exactly in its type.
void write_ply(const PointFile::Impl& impl, bool ascii, AtomicFile& out);

}  // namespace pnf
