// A small PLY reader written for pnf: no PLY library packaged for Debian does lossless PLY
// well. pnf needs list properties and unknown elements given back byte for byte, the header's
// comments and declared types kept, and every count checked against the file size before it
// is used to allocate; callback readers such as rply deliver only what they are asked for and
// re-encode values on the way out. So pnf parses PLY itself.
//
// Values are kept in the binary_little_endian layout whatever the encoding; a big-endian body
// is byte-swapped per value on the way in. An ascii body also keeps each token's text.
#include "ply_reader.hpp"

#include <charconv>
#include <cstdint>
#include <string_view>
#include <vector>

#include "byte_source.hpp"
#include "ply_scalar.hpp"
#include "pnf/error.hpp"
#include "row_layout.hpp"
#include "text_tokens.hpp"

namespace pnf {
namespace {

// Header lines are short ("property list uchar int vertex_indices"); a longer one means the
// header is missing its end and we are reading binary data.
constexpr std::size_t kMaxHeaderLine = 64 * 1024;

class PlyReader {
 public:
  PlyReader(const std::string& path, const ReadOptions& options) : source_(path), path_(path), options_(options) {}

  std::unique_ptr<PointFile::Impl> read() {
    impl_ = std::make_unique<PointFile::Impl>();
    impl_->source_format = PointFileFormat::ply;
    read_header();
    locate_vertex_fields(*impl_, path_);
    const bool ascii = impl_->header.encoding == PlyEncoding::ascii;
    const std::size_t element_count = impl_->header.elements.size();
    impl_->values.resize(element_count);
    if (ascii) impl_->ascii_rows.resize(element_count);
    std::vector<std::size_t> vertex_lines;
    for (std::size_t e = 0; e < element_count; ++e) {
      if (ascii) {
        read_ascii_element(e, e == impl_->vertex_element ? &vertex_lines : nullptr);
      } else {
        read_binary_element(e);
      }
    }
    if (ascii) {
      check_ascii_end();
    } else {
      check_binary_end();
    }
    check_vertices(*impl_, path_, vertex_lines, InvalidRows::nan_point, options_.check_normals);
    return std::move(impl_);
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw Error(ErrorCode::invalid_input, path_ + ": " + what); }

  [[noreturn]] void fail_header(const std::string& what) const {
    fail("header line " + std::to_string(line_number_) + ": " + what);
  }

  // ---- header ----

  void read_header() {
    std::string line;
    std::vector<std::string_view> tokens;
    bool have_format = false;
    std::size_t declarations = 0;  // format, element and property lines so far
    PlyHeader& header = impl_->header;
    header = PlyHeader{};
    for (;;) {
      const ByteSource::LineStatus status = source_.read_line(line, kMaxHeaderLine);
      ++line_number_;
      if (status == ByteSource::LineStatus::end_of_file) {
        if (line_number_ == 1) fail("not a PLY file: the file is empty");
        fail("the header has no end_header line (the file ends at line " + std::to_string(line_number_ - 1) + ")");
      }
      if (status == ByteSource::LineStatus::too_long) {
        if (line_number_ == 1) fail("not a PLY file: the first line is not 'ply'");
        fail_header("longer than " + std::to_string(kMaxHeaderLine) + " bytes; the header has no end_header line");
      }
      split_tokens(line, tokens);
      if (line_number_ == 1) {
        if (tokens.size() != 1 || tokens[0] != "ply") {
          fail("not a PLY file: the first line is not 'ply'");
        }
        continue;
      }
      if (tokens.empty()) continue;
      const std::string_view keyword = tokens[0];
      if (keyword == "comment" || keyword == "obj_info") {
        header.comments.push_back({std::string(keyword), comment_text(line, keyword), declarations});
      } else if (keyword == "format") {
        if (have_format) fail_header("a second format line");
        if (!header.elements.empty()) fail_header("the format line must come before elements");
        read_format(tokens);
        have_format = true;
        ++declarations;
      } else if (keyword == "element") {
        if (!have_format) fail_header("element before the format line");
        read_element(tokens);
        ++declarations;
      } else if (keyword == "property") {
        read_property(tokens);
        ++declarations;
      } else if (keyword == "end_header") {
        if (tokens.size() != 1) fail_header("unexpected text after end_header");
        if (!have_format) fail_header("end_header before any format line");
        return;
      } else {
        fail_header("unknown keyword '" + std::string(keyword) + "'");
      }
    }
  }

  // The rest of a comment line after the keyword and one separator, so that spacing inside
  // the comment survives.
  static std::string comment_text(const std::string& line, std::string_view keyword) {
    std::size_t start = line.find(keyword) + keyword.size();
    if (start < line.size()) ++start;
    return start < line.size() ? line.substr(start) : std::string();
  }

  void read_format(const std::vector<std::string_view>& tokens) {
    if (tokens.size() != 3) fail_header("expected 'format <encoding> <version>'");
    PlyHeader& header = impl_->header;
    bool known = false;
    for (const PlyEncoding e :
         {PlyEncoding::ascii, PlyEncoding::binary_little_endian, PlyEncoding::binary_big_endian}) {
      if (tokens[1] == to_string(e)) header.encoding = e, known = true;
    }
    if (!known) {
      fail_header("unknown format '" + std::string(tokens[1]) +
                  "' (expected ascii, binary_little_endian or binary_big_endian)");
    }
    header.version = std::string(tokens[2]);
  }

  void read_element(const std::vector<std::string_view>& tokens) {
    if (tokens.size() != 3) fail_header("expected 'element <name> <count>'");
    PlyElement element;
    element.name = std::string(tokens[1]);
    const std::string_view count = tokens[2];
    std::uint64_t value = 0;
    const auto result = std::from_chars(count.data(), count.data() + count.size(), value);
    if (result.ec != std::errc() || result.ptr != count.data() + count.size() ||
        value > static_cast<std::uint64_t>(SIZE_MAX)) {
      fail_header("element '" + element.name + "' count '" + std::string(count) + "' is not a non-negative integer");
    }
    element.count = static_cast<std::size_t>(value);
    for (const PlyElement& other : impl_->header.elements) {
      if (other.name == element.name) fail_header("a second element '" + element.name + "'");
    }
    impl_->header.elements.push_back(std::move(element));
  }

  PlyScalar scalar_type(std::string_view name) const {
    PlyScalar type = PlyScalar::float32;
    if (!parse_scalar_name(name, type)) {
      fail_header("unknown property type '" + std::string(name) + "'");
    }
    return type;
  }

  void read_property(const std::vector<std::string_view>& tokens) {
    if (impl_->header.elements.empty()) fail_header("property before any element");
    PlyElement& element = impl_->header.elements.back();
    PlyProperty property;
    if (tokens.size() >= 2 && tokens[1] == "list") {
      if (tokens.size() != 5) {
        fail_header("expected 'property list <count type> <item type> <name>'");
      }
      property.is_list = true;
      property.count_type = scalar_type(tokens[2]);
      property.count_type_name = std::string(tokens[2]);
      if (!is_integer(property.count_type)) {
        fail_header("list count type '" + property.count_type_name + "' is not an integer type");
      }
      property.type = scalar_type(tokens[3]);
      property.type_name = std::string(tokens[3]);
      property.name = std::string(tokens[4]);
    } else {
      if (tokens.size() != 3) fail_header("expected 'property <type> <name>'");
      property.type = scalar_type(tokens[1]);
      property.type_name = std::string(tokens[1]);
      property.name = std::string(tokens[2]);
    }
    for (const PlyProperty& other : element.properties) {
      if (other.name == property.name) {
        fail_header("a second property '" + property.name + "' in element '" + element.name + "'");
      }
    }
    element.properties.push_back(std::move(property));
  }

  // ---- binary body ----

  std::size_t read_bytes(std::vector<unsigned char>& bytes, std::size_t count) {
    const std::size_t old_size = bytes.size();
    bytes.resize(old_size + count);
    const std::size_t got = source_.read(bytes.data() + old_size, count);
    bytes.resize(old_size + got);
    return got;
  }

  [[noreturn]] void fail_row(const PlyElement& element, std::uint64_t row, const std::string& what) const {
    fail("element '" + element.name + "' row " + std::to_string(row) + ": " + what);
  }

  void read_binary_element(std::size_t e) {
    const PlyElement& element = impl_->header.elements[e];
    std::vector<unsigned char>& bytes = impl_->values[e];
    const bool swap = impl_->header.encoding == PlyEncoding::binary_big_endian;
    const RowLayout layout(element.properties);
    const std::size_t least_row = layout.row_size();
    const std::uint64_t remaining = source_.remaining();
    // Checked before anything is allocated: the count comes from an untrusted header.
    if (least_row > 0 && element.count > remaining / least_row) {
      const std::uint64_t row = remaining / least_row;
      fail_row(element, row,
               std::string("the file ends ") + (layout.fixed() && remaining % least_row == 0 ? "before" : "inside") +
                   " this row: the header declares " + std::to_string(element.count) + " rows of " +
                   (layout.fixed() ? "" : "at least ") + std::to_string(least_row) + " bytes but only " +
                   std::to_string(remaining) + " bytes remain (truncated file or wrong count)");
    }
    if (layout.fixed()) {
      const std::size_t total = element.count * least_row;
      if (read_bytes(bytes, total) != total) {
        fail_row(element, bytes.size() / least_row, "the file ends inside this row");
      }
      if (swap) swap_fixed_rows(element, bytes, least_row);
      return;
    }
    for (std::size_t row = 0; row < element.count; ++row) {
      for (const PlyProperty& property : element.properties) {
        read_binary_property(element, row, property, bytes, swap);
      }
    }
  }

  static void swap_fixed_rows(const PlyElement& element, std::vector<unsigned char>& bytes, std::size_t row_size) {
    for (std::size_t row = 0; row < element.count; ++row) {
      unsigned char* at = bytes.data() + row * row_size;
      for (const PlyProperty& property : element.properties) {
        const std::size_t size = scalar_size(property.type);
        reverse_bytes(at, size);
        at += size;
      }
    }
  }

  void read_binary_property(const PlyElement& element, std::size_t row, const PlyProperty& property,
                            std::vector<unsigned char>& bytes, bool swap) {
    const std::size_t item_size = scalar_size(property.type);
    if (!property.is_list) {
      if (read_bytes(bytes, item_size) != item_size) {
        fail_row(element, row, "the file ends inside this row");
      }
      if (swap) reverse_bytes(bytes.data() + bytes.size() - item_size, item_size);
      return;
    }
    const std::size_t count_size = scalar_size(property.count_type);
    if (read_bytes(bytes, count_size) != count_size) {
      fail_row(element, row, "the file ends inside this row");
    }
    unsigned char* count_bytes = bytes.data() + bytes.size() - count_size;
    if (swap) reverse_bytes(count_bytes, count_size);
    std::uint64_t count = 0;
    if (!load_count(property.count_type, count_bytes, count)) {
      fail_row(element, row, "list '" + property.name + "' has a negative count");
    }
    // Checked before allocating: the count is untrusted.
    if (count > source_.remaining() / item_size) {
      fail_row(element, row,
               "list '" + property.name + "' has " + std::to_string(count) + " items but only " +
                   std::to_string(source_.remaining()) + " bytes remain in the file");
    }
    const std::size_t start = bytes.size();
    read_bytes(bytes, count * item_size);
    if (swap) {
      for (std::size_t i = 0; i < count; ++i) {
        reverse_bytes(bytes.data() + start + i * item_size, item_size);
      }
    }
  }

  void check_binary_end() {
    const std::uint64_t extra = source_.remaining();
    if (!source_.rest_is_filler()) {
      fail(std::to_string(extra) + " bytes of data after the last element '" + impl_->header.elements.back().name +
           "' (do the header's counts match the data?)");
    }
  }

  // ---- ascii body ----

  // Reads the next non-blank line into line_. Returns false at the end of the file.
  bool next_data_line() {
    for (;;) {
      const ByteSource::LineStatus status = source_.read_line(line_, ByteSource::kMaxBodyLine);
      if (status == ByteSource::LineStatus::end_of_file) return false;
      ++line_number_;
      if (status == ByteSource::LineStatus::too_long) {
        fail("line " + std::to_string(line_number_) + ": longer than " + std::to_string(ByteSource::kMaxBodyLine) +
             " bytes");
      }
      split_tokens(line_, tokens_);
      if (!tokens_.empty()) return true;
    }
  }

  void read_ascii_element(std::size_t e, std::vector<std::size_t>* row_lines) {
    const PlyElement& element = impl_->header.elements[e];
    std::vector<unsigned char>& bytes = impl_->values[e];
    std::string& text = impl_->ascii_rows[e];
    // Rows without properties have no tokens; writers put an empty line, which is skipped
    // like any blank line, and the ascii writer writes one back from the count.
    if (element.properties.empty()) return;
    for (std::size_t row = 0; row < element.count; ++row) {
      if (!next_data_line()) {
        fail("line " + std::to_string(line_number_) + ": the file ends after " + std::to_string(row) + " of " +
             std::to_string(element.count) + " rows of element '" + element.name + "'");
      }
      if (row_lines) row_lines->push_back(line_number_);
      parse_ascii_row(element, row, bytes);
      for (std::size_t t = 0; t < tokens_.size(); ++t) {
        if (t > 0) text += ' ';
        text.append(tokens_[t].data(), tokens_[t].size());
      }
      text += '\n';
    }
  }

  [[noreturn]] void fail_ascii_row(const PlyElement& element, std::size_t row, const std::string& what) const {
    fail("line " + std::to_string(line_number_) + ", element '" + element.name + "' row " + std::to_string(row) + ": " +
         what);
  }

  // The number of tokens the row needs, from its list counts; "at least" while a count is
  // itself missing.
  std::string expected_tokens(const PlyElement& element) const {
    std::uint64_t needed = 0;
    for (const PlyProperty& property : element.properties) {
      if (!property.is_list) {
        ++needed;
        continue;
      }
      if (needed >= tokens_.size()) return "at least " + std::to_string(needed + 1);
      std::uint64_t count = 0;
      const std::string_view token = tokens_[needed];
      std::from_chars(token.data(), token.data() + token.size(), count);
      needed += 1 + count;
    }
    return std::to_string(needed);
  }

  void parse_ascii_row(const PlyElement& element, std::size_t row, std::vector<unsigned char>& bytes) {
    std::size_t t = 0;
    std::string why;
    const auto wrong_count = [&]() {
      fail_ascii_row(element, row,
                     "expected " + expected_tokens(element) + " values, found " + std::to_string(tokens_.size()));
    };
    const auto parse = [&](const PlyProperty& property, PlyScalar type) {
      if (t >= tokens_.size()) wrong_count();
      const std::size_t size = scalar_size(type);
      bytes.resize(bytes.size() + size);
      if (!parse_token(type, tokens_[t], bytes.data() + bytes.size() - size, why)) {
        fail_ascii_row(element, row,
                       "property '" + property.name + "': '" + std::string(tokens_[t]) + "' is " + why + " for " +
                           scalar_name(type));
      }
      ++t;
    };
    for (const PlyProperty& property : element.properties) {
      if (!property.is_list) {
        parse(property, property.type);
        continue;
      }
      parse(property, property.count_type);
      std::uint64_t count = 0;
      const std::size_t count_size = scalar_size(property.count_type);
      if (!load_count(property.count_type, bytes.data() + bytes.size() - count_size, count)) {
        fail_ascii_row(element, row, "list '" + property.name + "' has a negative count");
      }
      if (count > tokens_.size() - t) wrong_count();
      for (std::uint64_t i = 0; i < count; ++i) parse(property, property.type);
    }
    if (t != tokens_.size()) wrong_count();
  }

  void check_ascii_end() {
    if (next_data_line()) {
      fail("line " + std::to_string(line_number_) + ": data after the last element '" +
           impl_->header.elements.back().name + "' (do the header's counts match the data?)");
    }
  }

  ByteSource source_;
  std::string path_;
  ReadOptions options_;
  std::unique_ptr<PointFile::Impl> impl_;
  std::size_t line_number_ = 0;
  std::string line_;
  std::vector<std::string_view> tokens_;
};

}  // namespace

std::unique_ptr<PointFile::Impl> read_ply(const std::string& path, const ReadOptions& options) {
  return PlyReader(path, options).read();
}

}  // namespace pnf
