#include "text_points.hpp"

#include <charconv>
#include <string_view>
#include <vector>

#include "byte_source.hpp"
#include "ply_scalar.hpp"
#include "pnf/error.hpp"
#include "text_tokens.hpp"

namespace pnf {
namespace {

// Point lines are short; the cap only stops a file without newlines from being read whole into
// one string before it is rejected.
constexpr std::size_t kMaxLine = std::size_t{1} << 20;
// Text is handed to the file in pieces of about this size.
constexpr std::size_t kTextChunk = std::size_t{1} << 20;

bool is_count_line(const std::vector<std::string_view>& tokens) {
  if (tokens.size() != 1) return false;
  std::uint64_t count = 0;
  const std::string_view token = tokens[0];
  const auto result = std::from_chars(token.data(), token.data() + token.size(), count);
  return result.ec == std::errc() && result.ptr == token.data() + token.size();
}

std::unique_ptr<PointFile::Impl> make_impl(PointFileFormat format, bool normals) {
  auto impl = std::make_unique<PointFile::Impl>();
  impl->source_format = format;
  impl->added_normal_type = PlyScalar::float64;
  PlyElement vertex;
  vertex.name = "vertex";
  for (const char* name : {"x", "y", "z", "nx", "ny", "nz"}) {
    if (!normals && vertex.properties.size() == 3) break;
    PlyProperty property;
    property.name = name;
    property.type = PlyScalar::float64;
    property.type_name = "double";
    vertex.properties.push_back(property);
  }
  impl->header.elements.push_back(vertex);
  impl->values.resize(1);
  return impl;
}

}  // namespace

std::unique_ptr<PointFile::Impl> read_text_points(const std::string& path, PointFileFormat format,
                                                  const ReadOptions& options) {
  ByteSource source(path);
  const auto fail = [&path](std::size_t line, const std::string& what) {
    throw Error(ErrorCode::invalid_input, path + ": line " + std::to_string(line) + ": " + what);
  };
  std::unique_ptr<PointFile::Impl> impl;
  std::vector<std::size_t> row_lines;
  std::string line;
  std::vector<std::string_view> tokens;
  std::size_t line_number = 0;
  std::size_t values_per_line = 0;
  std::string why;
  for (;;) {
    const ByteSource::LineStatus status = source.read_line(line, kMaxLine);
    if (status == ByteSource::LineStatus::end_of_file) break;
    ++line_number;
    if (status == ByteSource::LineStatus::too_long) {
      fail(line_number, "longer than " + std::to_string(kMaxLine) + " bytes");
    }
    split_tokens(line, tokens);
    if (tokens.empty() || tokens[0][0] == '#') continue;
    if (!impl) {
      if (is_count_line(tokens)) continue;
      values_per_line = format == PointFileFormat::xyz ? tokens.size() : 6;
      if (format == PointFileFormat::xyz && values_per_line != 3 && values_per_line != 6) {
        fail(line_number, "expected 3 values (x y z) or 6 (x y z nx ny nz), found " + std::to_string(tokens.size()));
      }
      impl = make_impl(format, values_per_line == 6);
    }
    if (tokens.size() != values_per_line) {
      fail(line_number, "expected " + std::to_string(values_per_line) + " values (" +
                            (values_per_line == 6 ? "x y z nx ny nz" : "x y z") + "), found " +
                            std::to_string(tokens.size()));
    }
    std::vector<unsigned char>& bytes = impl->values[0];
    for (const std::string_view token : tokens) {
      bytes.resize(bytes.size() + sizeof(double));
      if (!parse_token(PlyScalar::float64, token, bytes.data() + bytes.size() - sizeof(double), why)) {
        fail(line_number, "'" + std::string(token) + "' is " + why);
      }
    }
    row_lines.push_back(line_number);
  }
  if (!impl) impl = make_impl(format, format != PointFileFormat::xyz);
  impl->header.elements[0].count = row_lines.size();
  locate_vertex_fields(*impl, path);
  check_vertices(*impl, path, row_lines, InvalidRows::none, options.check_normals);
  return impl;
}

void write_text_points(const PointCloud& cloud, AtomicFile& out) {
  std::string text;
  // 17 significant digits (%.17g) make every double read back exactly; to_chars, unlike
  // printf, ignores the locale's decimal separator. 32 characters hold one such value.
  char buffer[32];
  const auto put = [&](double value, char separator) {
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, 17);
    text.append(buffer, result.ptr);
    text += separator;
  };
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3& p = cloud.positions[i];
    put(p[0], ' ');
    put(p[1], ' ');
    if (!cloud.has_normals()) {
      put(p[2], '\n');
    } else {
      const Vec3& n = cloud.normals[i];
      put(p[2], ' ');
      put(n[0], ' ');
      put(n[1], ' ');
      put(n[2], '\n');
    }
    if (text.size() >= kTextChunk) {
      out.write(text);
      text.clear();
    }
  }
  out.write(text);
}

}  // namespace pnf
