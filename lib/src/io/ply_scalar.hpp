// PLY scalar values: sizes, type names, little-endian load/store, ascii parse and format.
// Values in memory are little-endian (the binary_little_endian layout) on every host.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "pnf/point_file.hpp"
#include "pnf/point_file_header.hpp"

namespace pnf {

// Size in bytes of one value of `type` (1, 2, 4 or 8).
std::size_t scalar_size(PlyScalar type);

// Parses a header type name ("uchar", "uint8", "float32", ...). Returns false when unknown.
bool parse_scalar_name(std::string_view name, PlyScalar& type);

// The short PLY name of `type` ("char", "uchar", ..., "float", "double"; "int64", "uint64" for
// the PCD-only types, which parse_scalar_name does not accept).
const char* scalar_name(PlyScalar type);

bool is_integer(PlyScalar type);

// Reverses the byte order of one value of `size` bytes in place.
void reverse_bytes(unsigned char* value, std::size_t size);

// The value at `bytes` (little-endian, of `type`) converted to double, exactly for every PLY
// scalar type; the 64-bit integers of PCD are rounded to nearest beyond 2^53.
double load_as_double(PlyScalar type, const unsigned char* bytes);

// Stores `value` at `bytes` as a little-endian float32 or float64 (rounded to nearest for
// float32). Precondition: `type` is float32 or float64.
void store_real(PlyScalar type, double value, unsigned char* bytes);

// Reads a list count of integer `count_type` at `bytes`. Returns false when it is negative.
bool load_count(PlyScalar count_type, const unsigned char* bytes, std::uint64_t& count);

// Parses an ascii token as a value of `type` and stores it little-endian at `bytes`. Integers
// must be integral and in range; reals are rounded to nearest in their own type ("nan" and
// "inf" accepted). On failure returns false and sets `why` ("not a number", "out of range for
// uchar").
bool parse_token(PlyScalar type, std::string_view token, unsigned char* bytes, std::string& why);

// Appends the value at `bytes` as ascii text: integers in decimal, reals as the shortest text
// that reads back to the same value in their own type.
void append_token(PlyScalar type, const unsigned char* bytes, std::string& out);

}  // namespace pnf
