// PCD is simple enough to read directly, and doing so keeps every value's bits and the whole
// header; PCL itself is far too large a dependency for a file reader. LZF comes from liblzf.
#include "pcd_reader.hpp"

#include <lzf.h>

#include <cerrno>
#include <cstring>
#include <limits>
#include <string_view>
#include <vector>

#include "byte_source.hpp"
#include "pcd_header.hpp"
#include "ply_scalar.hpp"
#include "pnf/error.hpp"
#include "text_tokens.hpp"

namespace pnf {
namespace {

// LZF's best case: a 3-byte back reference copies at most 264 bytes, so a block never
// decompresses to more than 88 times its size. A declared size beyond that is corrupt, and is
// refused before the output is allocated.
constexpr std::uint64_t kLzfMaxExpansion = 88;

class PcdReader {
 public:
  PcdReader(const std::string& path, const ReadOptions& options) : source_(path), path_(path), options_(options) {}

  std::unique_ptr<PointFile::Impl> read() {
    impl_ = std::make_unique<PointFile::Impl>();
    impl_->source_format = PointFileFormat::pcd;
    impl_->pcd = read_pcd_header(source_, header_lines_);
    const PcdHeader& header = impl_->pcd;
    impl_->header.encoding = PlyEncoding::binary_little_endian;
    impl_->header.elements.push_back(pcd_vertex_element(header));
    impl_->values.resize(1);
    locate_vertex_fields(*impl_, path_);
    switch (header.data) {
      case PcdData::ascii: read_ascii(); break;
      case PcdData::binary: read_binary(); break;
      case PcdData::binary_compressed: read_compressed(); break;
    }
    check_vertices(*impl_, path_, point_lines_, InvalidRows::any_nan_coordinate, options_.check_normals);
    return std::move(impl_);
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw Error(ErrorCode::invalid_input, path_ + ": " + what); }

  const PcdHeader& header() const { return impl_->pcd; }

  std::string declared(std::uint64_t point_bytes) const {
    return "the header declares " + std::to_string(header().points) + " points of " + std::to_string(point_bytes) +
           " bytes";
  }

  void check_end() {
    const std::uint64_t extra = source_.remaining();
    if (!source_.rest_is_filler()) {
      fail(std::to_string(extra) + " bytes of data after the last of " + std::to_string(header().points) +
           " points (do POINTS, WIDTH x HEIGHT and the fields' SIZE and COUNT match the data?)");
    }
  }

  // ---- binary ----

  void read_binary() {
    const std::uint64_t point_bytes = pcd_point_bytes(header(), true);
    const std::uint64_t remaining = source_.remaining();
    // Checked before anything is allocated: the counts come from an untrusted header.
    if (header().points > remaining / point_bytes) {
      fail("point " + std::to_string(remaining / point_bytes) + ": the file ends " +
           (remaining % point_bytes == 0 ? "before" : "inside") + " this point: " + declared(point_bytes) +
           " but only " + std::to_string(remaining) +
           " bytes follow DATA (truncated file, or wrong POINTS, SIZE or COUNT)");
    }
    std::vector<unsigned char>& values = impl_->values[0];
    values.resize(static_cast<std::size_t>(header().points * point_bytes));
    if (source_.read(values.data(), values.size()) != values.size()) fail("the file ends inside the data");
    check_end();
  }

  // ---- binary_compressed ----

  std::uint32_t load_u32(const unsigned char* bytes) const {
    return static_cast<std::uint32_t>(load_as_double(PlyScalar::uint32, bytes));
  }

  void read_compressed() {
    const PcdHeader& pcd = header();
    unsigned char sizes[8];
    if (source_.read(sizes, 8) != 8) {
      fail("the file ends inside the 8-byte size prefix of the binary_compressed data");
    }
    const std::uint64_t compressed_size = load_u32(sizes);
    const std::uint64_t uncompressed_size = load_u32(sizes + 4);
    const std::uint64_t packed_bytes = pcd_point_bytes(pcd, false);
    // packed_bytes >= 3: x, y and z are never padding.
    if (pcd.points > std::numeric_limits<std::uint32_t>::max() / packed_bytes) {
      fail(declared(packed_bytes) + ", more than the 4 GiB that binary_compressed's 32-bit sizes can hold");
    }
    const std::uint64_t needed = pcd.points * packed_bytes;
    if (uncompressed_size != needed) {
      fail("the compressed block declares " + std::to_string(uncompressed_size) + " uncompressed bytes, but " +
           declared(packed_bytes) + " (padding left out), " + std::to_string(needed) + " in all");
    }
    if (compressed_size > source_.remaining()) {
      fail("the compressed block declares " + std::to_string(compressed_size) + " bytes but only " +
           std::to_string(source_.remaining()) + " follow its size prefix (truncated file)");
    }
    if (needed > compressed_size * kLzfMaxExpansion) {
      fail("the compressed block of " + std::to_string(compressed_size) + " bytes cannot hold the declared " +
           std::to_string(needed) + " bytes (LZF expands at most " + std::to_string(kLzfMaxExpansion) + " times)");
    }
    std::vector<unsigned char> compressed(static_cast<std::size_t>(compressed_size));
    if (source_.read(compressed.data(), compressed.size()) != compressed.size()) {
      fail("the file ends inside the compressed block");
    }
    std::vector<unsigned char> packed(static_cast<std::size_t>(needed));
    if (needed > 0) {
      errno = 0;
      const unsigned int got = lzf_decompress(compressed.data(), static_cast<unsigned int>(compressed.size()),
                                              packed.data(), static_cast<unsigned int>(packed.size()));
      if (got != needed) {
        const int error_number = errno;
        std::string why;
        if (got == 0 && error_number == E2BIG) {
          why = "decompresses to more than";
        } else if (got == 0) {
          why = "is not valid LZF data; it does not decompress to";
        } else {
          why = "decompresses to " + std::to_string(got) + " bytes, not";
        }
        fail("the compressed block " + why + " the declared " + std::to_string(needed) + " bytes");
      }
    }
    check_end();
    unpack(packed);
  }

  // binary_compressed stores each field's values for all points in turn (x x x ... y y y ...),
  // the padding fields left out; rows put them back side by side, padding zero.
  void unpack(const std::vector<unsigned char>& packed) {
    const PcdHeader& pcd = header();
    const std::size_t points = pcd.points;
    const std::size_t point_bytes = static_cast<std::size_t>(pcd_point_bytes(pcd, true));
    std::vector<unsigned char>& values = impl_->values[0];
    values.assign(points * point_bytes, 0);
    std::size_t column = 0;  // offset of the field in a row
    const unsigned char* from = packed.data();
    for (const PcdField& field : pcd.fields) {
      const std::size_t bytes = std::size_t{field.size} * field.count;
      if (!is_pcd_padding(field)) {
        for (std::size_t p = 0; p < points; ++p, from += bytes) {
          std::memcpy(values.data() + p * point_bytes + column, from, bytes);
        }
      }
      column += bytes;
    }
  }

  // ---- ascii ----

  void read_ascii() {
    const PcdHeader& pcd = header();
    const std::size_t value_count = pcd_point_values(pcd);
    // Each value takes a character and a separator (a space, or the line end), so N points of
    // V values need at least 2 N V - 1 bytes; checked before anything is allocated.
    const std::uint64_t remaining = source_.remaining();
    if (pcd.points > 0 && pcd.points > (remaining + 1) / (2 * std::uint64_t{value_count})) {
      fail("the header declares " + std::to_string(pcd.points) + " points of " + std::to_string(value_count) +
           " values, but only " + std::to_string(remaining) + " bytes of text follow DATA (truncated file, or " +
           "wrong POINTS)");
    }
    const PlyElement& vertex = impl_->header.elements[0];
    const std::size_t point_bytes = static_cast<std::size_t>(pcd_point_bytes(pcd, true));
    std::vector<unsigned char>& values = impl_->values[0];
    values.resize(pcd.points * point_bytes);
    point_lines_.reserve(pcd.points);
    std::string line, why;
    std::vector<std::string_view> tokens;
    std::size_t line_number = header_lines_;
    const auto next_line = [&]() {
      for (;;) {
        const ByteSource::LineStatus status = source_.read_line(line, ByteSource::kMaxBodyLine);
        if (status == ByteSource::LineStatus::end_of_file) return false;
        ++line_number;
        if (status == ByteSource::LineStatus::too_long) {
          fail("line " + std::to_string(line_number) + ": longer than " + std::to_string(ByteSource::kMaxBodyLine) +
               " bytes");
        }
        split_tokens(line, tokens);
        if (!tokens.empty()) return true;
      }
    };
    for (std::size_t point = 0; point < pcd.points; ++point) {
      if (!next_line()) {
        fail("line " + std::to_string(line_number) + ": the file ends after " + std::to_string(point) + " of " +
             std::to_string(pcd.points) + " points");
      }
      point_lines_.push_back(line_number);
      const std::string where = "line " + std::to_string(line_number) + ", point " + std::to_string(point);
      if (tokens.size() != value_count) {
        fail(where + ": expected " + std::to_string(value_count) + " values (the fields' COUNT), found " +
             std::to_string(tokens.size()));
      }
      unsigned char* row = values.data() + point * point_bytes;
      std::size_t t = 0;
      for (const PcdField& field : pcd.fields) {
        for (std::size_t i = 0; i < field.count; ++i, ++t) {
          const PlyProperty& property = vertex.properties[t];
          if (!parse_value(field, property.type, tokens[t], row, why)) {
            fail(where + ", field '" + field.name + "': '" + std::string(tokens[t]) + "' is " + why + " for TYPE " +
                 field.type + " SIZE " + std::to_string(field.size));
          }
          row += field.size;
        }
      }
    }
    if (next_line()) {
      fail("line " + std::to_string(line_number) + ": data after the last of " + std::to_string(pcd.points) +
           " points (do POINTS and WIDTH x HEIGHT match the data?)");
    }
  }

  // PCL writes a packed colour (F 4 rgb) as the decimal text of its bits; plain digits are
  // read so, anything else as a float.
  static bool parse_value(const PcdField& field, PlyScalar type, std::string_view token, unsigned char* at,
                          std::string& why) {
    if (is_pcd_packed_colour(field) && !token.empty() &&
        token.find_first_not_of("0123456789") == std::string_view::npos) {
      return parse_token(PlyScalar::uint32, token, at, why);
    }
    return parse_token(type, token, at, why);
  }

  ByteSource source_;
  std::string path_;
  ReadOptions options_;
  std::unique_ptr<PointFile::Impl> impl_;
  std::vector<std::size_t> point_lines_;  // ascii: the file line of each point
  std::size_t header_lines_ = 0;          // lines up to and including DATA
};

}  // namespace

std::unique_ptr<PointFile::Impl> read_pcd(const std::string& path, const ReadOptions& options) {
  return PcdReader(path, options).read();
}

}  // namespace pnf
