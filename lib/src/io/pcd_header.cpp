#include "pcd_header.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <string_view>
#include <vector>

#include "ply_scalar.hpp"
#include "pnf/error.hpp"
#include "text_tokens.hpp"

namespace pnf {
namespace {

// Header lines are short; a longer one means the header has no DATA line and we are reading
// the body.
constexpr std::size_t kMaxHeaderLine = 64 * 1024;
// The first line PCL writes, and pnf when the source had no comments.
constexpr const char* kStandardComment = "# .PCD v0.7 - Point Cloud Data file format";

struct PcdType {
  char type;
  unsigned size;
  PlyScalar scalar;
};

constexpr PcdType kPcdTypes[] = {
    {'I', 1, PlyScalar::int8},    {'U', 1, PlyScalar::uint8}, {'I', 2, PlyScalar::int16},
    {'U', 2, PlyScalar::uint16},  {'I', 4, PlyScalar::int32}, {'U', 4, PlyScalar::uint32},
    {'F', 4, PlyScalar::float32}, {'I', 8, PlyScalar::int64}, {'U', 8, PlyScalar::uint64},
    {'F', 8, PlyScalar::float64},
};

// True when `line` cannot be a header line but reads as a point's values: a byte outside
// printable ASCII (a binary body), or every token a number (an ascii body, "nan" included).
bool looks_like_point_data(std::string_view line, const std::vector<std::string_view>& tokens) {
  for (const char c : line) {
    const auto byte = static_cast<unsigned char>(c);
    if ((byte < 0x20 && !is_blank_char(c)) || byte >= 0x7f) return true;
  }
  for (const std::string_view token : tokens) {
    double value = 0;
    const auto result = std::from_chars(token.data(), token.data() + token.size(), value);
    if (result.ec != std::errc() || result.ptr != token.data() + token.size()) return false;
  }
  return true;
}

class HeaderParser {
 public:
  explicit HeaderParser(ByteSource& source) : source_(source) {}

  PcdHeader parse(std::size_t& lines) {
    std::string line;
    std::vector<std::string_view> tokens;
    for (;;) {
      const ByteSource::LineStatus status = source_.read_line(line, kMaxHeaderLine);
      ++line_number_;
      if (status == ByteSource::LineStatus::end_of_file) {
        if (line_number_ == 1) fail("not a PCD file: the file is empty");
        fail("the header has no DATA line (the file ends at line " + std::to_string(line_number_ - 1) + ")");
      }
      if (status == ByteSource::LineStatus::too_long) {
        fail_line("longer than " + std::to_string(kMaxHeaderLine) + " bytes; the header has no DATA line");
      }
      split_tokens(line, tokens);
      if (tokens.empty()) continue;
      const std::string_view keyword = tokens[0];
      if (keyword[0] == '#') {
        header_.comments.push_back(line);
        continue;
      }
      const std::vector<std::string_view> values(tokens.begin() + 1, tokens.end());
      if (keyword == "DATA") {
        read_data(values);
        break;
      }
      if (looks_like_point_data(line, tokens)) {
        // The body began where DATA should have been; its bytes are not quoted (a NUL would cut
        // the message short).
        fail_line(
            "point data where a header line should be: the header has no DATA line (DATA ascii, binary or "
            "binary_compressed) before it");
      }
      read_line(keyword, values);
    }
    finish();
    lines = line_number_;
    return std::move(header_);
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(ErrorCode::invalid_input, source_.path() + ": " + what);
  }
  [[noreturn]] void fail_line(const std::string& what) const {
    fail("header line " + std::to_string(line_number_) + ": " + what);
  }

  void once(bool& seen, std::string_view keyword) {
    if (seen) fail_line("a second " + std::string(keyword) + " line");
    seen = true;
  }

  std::uint64_t integer(std::string_view keyword, std::string_view token) const {
    std::uint64_t value = 0;
    const auto result = std::from_chars(token.data(), token.data() + token.size(), value);
    if (result.ec != std::errc() || result.ptr != token.data() + token.size() ||
        value > static_cast<std::uint64_t>(std::numeric_limits<std::size_t>::max())) {
      fail_line(std::string(keyword) + " '" + std::string(token) + "' is not a non-negative integer");
    }
    return value;
  }

  std::size_t single_integer(std::string_view keyword, const std::vector<std::string_view>& values) const {
    if (values.size() != 1) fail_line("expected '" + std::string(keyword) + " <count>'");
    return static_cast<std::size_t>(integer(keyword, values[0]));
  }

  // SIZE, TYPE and COUNT give one entry per field.
  void check_arity(std::string_view keyword, const std::vector<std::string_view>& values) const {
    if (!seen_fields_) fail_line(std::string(keyword) + " before FIELDS");
    if (values.size() != header_.fields.size()) {
      fail_line(std::string(keyword) + " has " + std::to_string(values.size()) + " entries but FIELDS names " +
                std::to_string(header_.fields.size()) + " fields");
    }
  }

  std::string field_name(std::size_t f) const { return "field '" + header_.fields[f].name + "'"; }

  void read_line(std::string_view keyword, const std::vector<std::string_view>& values) {
    std::vector<PcdField>& fields = header_.fields;
    if (keyword == "VERSION") {
      once(seen_version_, keyword);
      if (values.size() != 1) fail_line("expected 'VERSION <version>'");
      header_.version = std::string(values[0]);
    } else if (keyword == "FIELDS" || keyword == "COLUMNS") {  // COLUMNS: PCL's name before v0.7
      once(seen_fields_, "FIELDS");
      if (values.empty()) fail_line("FIELDS names no field");
      if (values.size() > kPcdMaxValuesPerPoint)
        fail_line("FIELDS names more than " + std::to_string(kPcdMaxValuesPerPoint) + " fields");
      for (const std::string_view name : values) {
        PcdField field;
        field.name = std::string(name);
        for (const PcdField& other : fields) {
          if (other.name == field.name && !is_pcd_padding(field)) fail_line("a second field '" + field.name + "'");
        }
        fields.push_back(std::move(field));
      }
    } else if (keyword == "SIZE") {
      once(seen_size_, keyword);
      check_arity(keyword, values);
      for (std::size_t f = 0; f < fields.size(); ++f) {
        const std::uint64_t size = integer("SIZE of " + field_name(f), values[f]);
        if (size != 1 && size != 2 && size != 4 && size != 8) {
          fail_line("SIZE of " + field_name(f) + " is " + std::to_string(size) + " (expected 1, 2, 4 or 8)");
        }
        fields[f].size = static_cast<unsigned>(size);
      }
    } else if (keyword == "TYPE") {
      once(seen_type_, keyword);
      check_arity(keyword, values);
      for (std::size_t f = 0; f < fields.size(); ++f) {
        if (values[f] != "I" && values[f] != "U" && values[f] != "F") {
          fail_line("TYPE of " + field_name(f) + " is '" + std::string(values[f]) + "' (expected I, U or F)");
        }
        fields[f].type = values[f][0];
      }
    } else if (keyword == "COUNT") {
      once(seen_count_, keyword);
      check_arity(keyword, values);
      for (std::size_t f = 0; f < fields.size(); ++f) {
        const std::uint64_t count = integer("COUNT of " + field_name(f), values[f]);
        if (count == 0 || count > kPcdMaxValuesPerPoint) {
          fail_line("COUNT of " + field_name(f) + " is " + std::to_string(count) + " (expected 1 to " +
                    std::to_string(kPcdMaxValuesPerPoint) + ")");
        }
        fields[f].count = static_cast<std::size_t>(count);
      }
    } else if (keyword == "WIDTH") {
      once(seen_width_, keyword);
      header_.width = single_integer(keyword, values);
    } else if (keyword == "HEIGHT") {
      once(seen_height_, keyword);
      header_.height = single_integer(keyword, values);
    } else if (keyword == "POINTS") {
      once(seen_points_, keyword);
      header_.points = single_integer(keyword, values);
    } else if (keyword == "VIEWPOINT") {
      once(seen_viewpoint_, keyword);
      if (values.size() != 7)
        fail_line("VIEWPOINT has " + std::to_string(values.size()) + " values (expected 7: tx ty tz qw qx qy qz)");
      for (std::size_t i = 0; i < 7; ++i) {
        double value = 0;
        const std::string_view token = values[i];
        const auto result = std::from_chars(token.data(), token.data() + token.size(), value);
        if (result.ec != std::errc() || result.ptr != token.data() + token.size() || !std::isfinite(value)) {
          fail_line("VIEWPOINT value " + std::to_string(i + 1) + " '" + std::string(token) +
                    "' is not a finite number");
        }
        header_.viewpoint[i] = value;
      }
    } else {
      fail_line("unknown keyword '" + std::string(keyword) + "'");
    }
  }

  void read_data(const std::vector<std::string_view>& values) {
    if (values.size() != 1) fail_line("expected 'DATA ascii', 'DATA binary' or 'DATA binary_compressed'");
    for (const PcdData data : {PcdData::ascii, PcdData::binary, PcdData::binary_compressed}) {
      if (values[0] == to_string(data)) {
        header_.data = data;
        return;
      }
    }
    fail_line("unknown DATA '" + std::string(values[0]) + "' (expected ascii, binary or binary_compressed)");
  }

  // Checks made once the whole header is known; messages name the DATA line's header.
  void finish() {
    std::vector<PcdField>& fields = header_.fields;
    if (!seen_fields_) fail("the header has no FIELDS line");
    std::size_t values = 0;
    for (std::size_t f = 0; f < fields.size(); ++f) {
      PlyScalar scalar;
      if (!pcd_scalar(fields[f].type, fields[f].size, scalar)) {
        fail("header: " + field_name(f) + " has TYPE " + fields[f].type + " with SIZE " +
             std::to_string(fields[f].size) + ", not a PCD type (F takes SIZE 4 or 8)");
      }
      values += fields[f].count;
    }
    if (values > kPcdMaxValuesPerPoint) {
      fail("header: the fields hold " + std::to_string(values) + " values a point (at most " +
           std::to_string(kPcdMaxValuesPerPoint) + ")");
    }
    for (const char* axis : {"x", "y", "z"}) {
      bool found = false;
      for (const PcdField& field : fields) {
        if (field.name != axis) continue;
        found = true;
        if (field.count != 1)
          fail("header: field '" + field.name + "' has COUNT " + std::to_string(field.count) + " (expected 1)");
      }
      if (!found) fail(std::string("header: no field '") + axis + "' (FIELDS must name x, y and z)");
    }
    if (!seen_width_ && !seen_height_) {
      if (!seen_points_) fail("header: no WIDTH, HEIGHT or POINTS line");
      header_.width = header_.points;
      header_.height = 1;
    } else if (!seen_width_) {
      fail("header: HEIGHT " + std::to_string(header_.height) + " without WIDTH");
    } else if (!seen_height_) {
      header_.height = 1;
    }
    const std::size_t width = header_.width, height = header_.height;
    const bool overflows = height != 0 && width > std::numeric_limits<std::size_t>::max() / height;
    if (!seen_points_ && !overflows) header_.points = width * height;
    if (overflows || width * height != header_.points) {
      fail("header: POINTS " + std::to_string(header_.points) + " disagrees with WIDTH " + std::to_string(width) +
           " x HEIGHT " + std::to_string(height) + (overflows ? "" : " = " + std::to_string(width * height)));
    }
  }

  ByteSource& source_;
  PcdHeader header_;
  std::size_t line_number_ = 0;
  bool seen_version_ = false, seen_fields_ = false, seen_size_ = false, seen_type_ = false, seen_count_ = false;
  bool seen_width_ = false, seen_height_ = false, seen_points_ = false, seen_viewpoint_ = false;
};

void append_double(double value, std::string& out) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

}  // namespace

const char* to_string(PcdData data) {
  switch (data) {
    case PcdData::ascii: return "ascii";
    case PcdData::binary: return "binary";
    case PcdData::binary_compressed: return "binary_compressed";
  }
  return "binary";
}

bool pcd_scalar(char type, unsigned size, PlyScalar& scalar) {
  for (const PcdType& entry : kPcdTypes) {
    if (entry.type == type && entry.size == size) {
      scalar = entry.scalar;
      return true;
    }
  }
  return false;
}

void pcd_type_of(PlyScalar scalar, char& type, unsigned& size) {
  for (const PcdType& entry : kPcdTypes) {
    if (entry.scalar == scalar) {
      type = entry.type;
      size = entry.size;
      return;
    }
  }
  type = 'F';
  size = 8;
}

std::uint64_t pcd_point_bytes(const PcdHeader& header, bool with_padding) {
  std::uint64_t bytes = 0;
  for (const PcdField& field : header.fields) {
    if (with_padding || !is_pcd_padding(field)) bytes += std::uint64_t{field.size} * field.count;
  }
  return bytes;
}

std::size_t pcd_point_values(const PcdHeader& header) {
  std::size_t values = 0;
  for (const PcdField& field : header.fields) values += field.count;
  return values;
}

PcdHeader read_pcd_header(ByteSource& source, std::size_t& lines) { return HeaderParser(source).parse(lines); }

PlyElement pcd_vertex_element(const PcdHeader& header) {
  PlyElement vertex;
  vertex.name = "vertex";
  vertex.count = header.points;
  vertex.properties.reserve(pcd_point_values(header));
  for (const PcdField& field : header.fields) {
    PlyProperty property;
    pcd_scalar(field.type, field.size, property.type);
    property.type_name = scalar_name(property.type);
    for (std::size_t i = 0; i < field.count; ++i) {
      property.name = field.count == 1 ? field.name : field.name + "_" + std::to_string(i);
      vertex.properties.push_back(property);
    }
  }
  return vertex;
}

std::string pcd_header_text(const PcdHeader& header, PcdData data) {
  const bool ascii = data == PcdData::ascii;
  std::string text = std::string(kStandardComment) + '\n';
  for (const std::string& comment : header.comments) {
    // The format line names the version, and pnf writes 0.7 whatever it read.
    if (comment.rfind("# .PCD v", 0) != 0) text += comment + '\n';
  }
  std::string names, sizes, types, counts;
  for (const PcdField& field : header.fields) {
    if (ascii && is_pcd_padding(field)) continue;
    names += ' ' + field.name;
    sizes += ' ' + std::to_string(field.size);
    types += ' ';
    types += ascii && is_pcd_packed_colour(field) ? 'U' : field.type;
    counts += ' ' + std::to_string(field.count);
  }
  text += "VERSION 0.7\nFIELDS" + names + "\nSIZE" + sizes + "\nTYPE" + types + "\nCOUNT" + counts;
  text += "\nWIDTH " + std::to_string(header.width) + "\nHEIGHT " + std::to_string(header.height) + "\nVIEWPOINT";
  for (const double value : header.viewpoint) {
    text += ' ';
    append_double(value, text);
  }
  text += "\nPOINTS " + std::to_string(header.points) + "\nDATA " + to_string(data) + '\n';
  return text;
}

}  // namespace pnf
