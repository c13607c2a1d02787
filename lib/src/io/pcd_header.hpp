// PCD headers (PCL's Point Cloud Data, v0.6 and v0.7): parsing, checking, the field types,
// the equivalent PLY vertex element, and the header text pnf writes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "byte_source.hpp"
#include "pnf/point_file.hpp"
#include "pnf/point_file_header.hpp"

namespace pnf {

// The largest number of values (the sum of COUNT over the fields) a point may have. PCL's
// largest common descriptors hold a few hundred (SHOT 352, ESF 640); a bound keeps a corrupt
// COUNT from allocating a property per value before the file size can refute it.
constexpr std::size_t kPcdMaxValuesPerPoint = std::size_t{1} << 16;

// The scalar type of a PCD (TYPE, SIZE) pair, as PCL defines them: I and U with SIZE 1, 2, 4
// or 8, F with SIZE 4 or 8. Returns false for any other pair.
bool pcd_scalar(char type, unsigned size, PlyScalar& scalar);

// The PCD TYPE letter and SIZE of `scalar`.
void pcd_type_of(PlyScalar scalar, char& type, unsigned& size);

// True for PCL's padding field "_" (bytes between fields that hold no value).
inline bool is_pcd_padding(const PcdField& field) { return field.name == "_"; }

// True for a field whose ascii form follows PCL's packed-colour convention: F 4 named rgb or
// rgba, written as its bits in decimal (as floats, many opaque colours are NaN).
inline bool is_pcd_packed_colour(const PcdField& field) {
  return field.type == 'F' && field.size == 4 && (field.name == "rgb" || field.name == "rgba");
}

// Bytes of one point: every field (`with_padding`) or only the fields that are not "_"
// (the layout of binary_compressed).
std::uint64_t pcd_point_bytes(const PcdHeader& header, bool with_padding);

// Values (the sum of COUNT) of one point.
std::size_t pcd_point_values(const PcdHeader& header);

// Reads the header from `source` up to and including its DATA line, and checks it: SIZE,
// TYPE and COUNT have one entry per FIELDS name, every (TYPE, SIZE) is a PCD type, x y z are
// fields of COUNT 1, names are unique (except "_"), POINTS equals WIDTH x HEIGHT. Missing
// SIZE, TYPE or COUNT default as in PCL (4, F, 1), a missing HEIGHT to 1, missing WIDTH and
// HEIGHT to POINTS x 1. Sets `lines` to the number of lines read (the DATA line's number).
// Throws invalid_input "<path>: header line N: ..." naming the field or keyword and what is
// wrong.
PcdHeader read_pcd_header(ByteSource& source, std::size_t& lines);

// The PLY vertex element equivalent to `header`: one scalar property per value, named after
// its field (name_0 ... name_{k-1} for a field of COUNT k > 1), `header.points` rows.
PlyElement pcd_vertex_element(const PcdHeader& header);

// The header text pnf writes for `header` with DATA `data`, ending in "DATA ...\n": VERSION
// 0.7, the comments kept (the standard first line when there are none); for ascii the padding
// fields are left out and packed colours are declared U.
std::string pcd_header_text(const PcdHeader& header, PcdData data);

}  // namespace pnf
