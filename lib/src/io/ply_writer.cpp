#include "ply_writer.hpp"

#include <algorithm>
#include <cstdint>
#include <string>

#include "ply_scalar.hpp"
#include "row_layout.hpp"

namespace pnf {
namespace {

// Text is handed to the file in pieces of about this size, to bound the memory used for
// formatting.
constexpr std::size_t kTextChunk = std::size_t{1} << 20;

}  // namespace

std::string header_text(const PlyHeader& header, bool ascii) {
  std::string text = "ply\n";
  std::size_t declarations = 0;
  std::size_t next_comment = 0;
  // Comments go back where they stood: before the declaration they preceded.
  const auto put_comments = [&](std::size_t up_to) {
    while (next_comment < header.comments.size() && header.comments[next_comment].position <= up_to) {
      const PlyComment& comment = header.comments[next_comment++];
      text += comment.keyword;
      if (!comment.text.empty()) text += ' ' + comment.text;
      text += '\n';
    }
  };
  put_comments(declarations++);
  text += "format ";
  text += to_string(ascii ? PlyEncoding::ascii : PlyEncoding::binary_little_endian);
  text += ' ' + header.version + '\n';
  for (const PlyElement& element : header.elements) {
    put_comments(declarations++);
    text += "element " + element.name + ' ' + std::to_string(element.count) + '\n';
    for (const PlyProperty& property : element.properties) {
      put_comments(declarations++);
      text += "property ";
      if (property.is_list) text += "list " + property.count_type_name + ' ';
      text += property.type_name + ' ' + property.name + '\n';
    }
  }
  put_comments(static_cast<std::size_t>(-1));
  text += "end_header\n";
  return text;
}

namespace {

void write_formatted_rows(const PlyElement& element, const std::vector<unsigned char>& values, AtomicFile& out) {
  RowLayout layout(element.properties);
  std::string text;
  const unsigned char* row = values.data();
  for (std::size_t r = 0; r < element.count; ++r) {
    const std::size_t row_size = layout.measure(row);
    for (std::size_t p = 0; p < element.properties.size(); ++p) {
      const PlyProperty& property = element.properties[p];
      const unsigned char* at = row + layout.offset(p);
      if (p > 0) text += ' ';
      if (!property.is_list) {
        append_token(property.type, at, text);
        continue;
      }
      std::uint64_t count = 0;
      load_count(property.count_type, at, count);
      append_token(property.count_type, at, text);
      at += scalar_size(property.count_type);
      for (std::uint64_t i = 0; i < count; ++i) {
        text += ' ';
        append_token(property.type, at, text);
        at += scalar_size(property.type);
      }
    }
    text += '\n';
    if (text.size() >= kTextChunk) {
      out.write(text);
      text.clear();
    }
    row += row_size;
  }
  out.write(text);
}

}  // namespace

void write_ply(const PointFile::Impl& impl, bool ascii, AtomicFile& out) {
  out.write(header_text(impl.header, ascii));
  const std::vector<PlyElement>& elements = impl.header.elements;
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const PlyElement& element = elements[e];
    if (!ascii) {
      out.write(impl.values[e].data(), impl.values[e].size());
    } else if (element.properties.empty()) {
      // One empty line per row, as other writers do; not stored, since it is only the count.
      const std::string lines(std::min(element.count, kTextChunk), '\n');
      for (std::size_t done = 0; done < element.count; done += lines.size()) {
        out.write(lines.data(), std::min(lines.size(), element.count - done));
      }
    } else if (!impl.ascii_rows.empty()) {
      out.write(impl.ascii_rows[e]);
    } else {
      write_formatted_rows(element, impl.values[e], out);
    }
  }
}

}  // namespace pnf
