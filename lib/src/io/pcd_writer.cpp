#include "pcd_writer.hpp"

#include <lzf.h>

#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "pcd_header.hpp"
#include "ply_scalar.hpp"
#include "pnf/error.hpp"

namespace pnf {
namespace {

// Text is handed to the file in pieces of about this size, to bound the memory used for
// formatting.
constexpr std::size_t kTextChunk = std::size_t{1} << 20;

// The PCD header for a file that did not come from PCD: one field per scalar vertex property.
PcdHeader header_for(const PointFile::Impl& impl, const std::string& path) {
  const PlyElement& vertex = impl.header.elements[impl.vertex_element];
  PcdHeader header;
  header.width = vertex.count;
  header.height = 1;
  header.points = vertex.count;
  header.data = PcdData::binary;
  for (const PlyProperty& property : vertex.properties) {
    if (property.is_list) {
      throw Error(ErrorCode::invalid_argument,
                  path + ": vertex property '" + property.name + "' is a list, and PCD has no lists");
    }
    PcdField field;
    field.name = property.name;
    if (field.name == "nx") field.name = "normal_x";
    if (field.name == "ny") field.name = "normal_y";
    if (field.name == "nz") field.name = "normal_z";
    pcd_type_of(property.type, field.type, field.size);
    header.fields.push_back(std::move(field));
  }
  return header;
}

void write_compressed(const PcdHeader& header, const std::vector<unsigned char>& values, const std::string& path,
                      AtomicFile& out) {
  const std::uint64_t packed_bytes = pcd_point_bytes(header, false);
  const std::size_t point_bytes = static_cast<std::size_t>(pcd_point_bytes(header, true));
  const std::size_t points = header.points;
  if (points > std::numeric_limits<std::uint32_t>::max() / packed_bytes) {
    throw Error(ErrorCode::invalid_argument,
                path + ": " + std::to_string(points) + " points of " + std::to_string(packed_bytes) +
                    " bytes pass the 4 GiB that binary_compressed's 32-bit sizes can hold; use binary");
  }
  // Field by field, as PCL lays it out (x x x ... y y y ...), without the padding.
  std::vector<unsigned char> packed(static_cast<std::size_t>(points * packed_bytes));
  unsigned char* to = packed.data();
  std::size_t column = 0;
  for (const PcdField& field : header.fields) {
    const std::size_t bytes = std::size_t{field.size} * field.count;
    if (!is_pcd_padding(field)) {
      for (std::size_t p = 0; p < points; ++p, to += bytes)
        std::memcpy(to, values.data() + p * point_bytes + column, bytes);
    }
    column += bytes;
  }
  // LZF grows incompressible data by at most one byte in 32, plus a little.
  std::vector<unsigned char> compressed(packed.size() + packed.size() / 16 + 64);
  unsigned int compressed_size = 0;
  if (!packed.empty()) {
    compressed_size = lzf_compress(packed.data(), static_cast<unsigned int>(packed.size()), compressed.data(),
                                   static_cast<unsigned int>(compressed.size()));
    if (compressed_size == 0) {
      throw Error(ErrorCode::io, path + ": LZF compression of " + std::to_string(packed.size()) +
                                     " bytes did not fit its output buffer");
    }
  }
  unsigned char sizes[8];
  const std::uint32_t both[2] = {compressed_size, static_cast<std::uint32_t>(packed.size())};
  for (int i = 0; i < 2; ++i) {
    // Little-endian, as PCL writes it on the hosts it runs on.
    for (int b = 0; b < 4; ++b) sizes[4 * i + b] = static_cast<unsigned char>(both[i] >> (8 * b));
  }
  out.write(sizes, sizeof sizes);
  out.write(compressed.data(), compressed_size);
}

void write_ascii(const PcdHeader& header, const std::vector<unsigned char>& values, AtomicFile& out) {
  const std::size_t point_bytes = static_cast<std::size_t>(pcd_point_bytes(header, true));
  std::vector<PlyScalar> types;
  for (const PcdField& field : header.fields) {
    PlyScalar type = PlyScalar::float32;
    pcd_scalar(field.type, field.size, type);
    types.push_back(is_pcd_packed_colour(field) ? PlyScalar::uint32 : type);
  }
  std::string text;
  for (std::size_t p = 0; p < header.points; ++p) {
    const unsigned char* at = values.data() + p * point_bytes;
    bool first = true;
    for (std::size_t f = 0; f < header.fields.size(); ++f) {
      const PcdField& field = header.fields[f];
      for (std::size_t i = 0; i < field.count; ++i, at += field.size) {
        if (is_pcd_padding(field)) continue;
        if (!first) text += ' ';
        first = false;
        append_token(types[f], at, text);
      }
    }
    text += '\n';
    if (text.size() >= kTextChunk) {
      out.write(text);
      text.clear();
    }
  }
  out.write(text);
}

}  // namespace

void write_pcd(const PointFile::Impl& impl, PcdData data, const std::string& path, AtomicFile& out) {
  const PcdHeader header = impl.source_format == PointFileFormat::pcd ? impl.pcd : header_for(impl, path);
  const std::vector<unsigned char>& values = impl.values[impl.vertex_element];
  out.write(pcd_header_text(header, data));
  switch (data) {
    case PcdData::binary: out.write(values.data(), values.size()); break;
    case PcdData::binary_compressed: write_compressed(header, values, path, out); break;
    case PcdData::ascii: write_ascii(header, values, out); break;
  }
}

}  // namespace pnf
