// Test helpers for the point-file tests: a small model of a PLY file (elements, properties and
// each value's ascii token) that writes the file in any encoding, independently of pnf's reader
// and writer, plus whole-file read/write (and the temporary folder of temp_dir.hpp).
#pragma once

#include <gtest/gtest.h>
#include <stdlib.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "temp_dir.hpp"

namespace pnf::test {

struct Column {
  std::string type;  // header spelling: "float", "uint8", ...
  std::string name;
  std::string count_type;  // lists only: header spelling of the count type
};

struct Element {
  std::string name;
  std::vector<Column> columns;
  // One row per entry, its ascii tokens in order; a list is its count token then its items.
  std::vector<std::vector<std::string>> rows;
};

struct PlyModel {
  std::vector<std::string> comments;  // whole lines ("comment ..." / "obj_info ..."), after format
  std::vector<Element> elements;
};

enum class Encoding { ascii, little_endian, big_endian };

inline std::size_t type_size(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "double" || type == "float64") return 8;
  return 4;
}

// The little-endian bytes of `token` read as a value of `type` (strtof/strtod/strtoll, not
// pnf's parser).
inline std::vector<unsigned char> token_bytes(const std::string& type, const std::string& token) {
  const std::size_t size = type_size(type);
  std::vector<unsigned char> bytes(size);
  std::uint64_t bits = 0;
  if (type == "float" || type == "float32") {
    const float value = std::strtof(token.c_str(), nullptr);
    std::uint32_t raw;
    std::memcpy(&raw, &value, 4);
    bits = raw;
  } else if (type == "double" || type == "float64") {
    const double value = std::strtod(token.c_str(), nullptr);
    std::memcpy(&bits, &value, 8);
  } else {
    bits = static_cast<std::uint64_t>(std::strtoll(token.c_str(), nullptr, 10));
  }
  for (std::size_t i = 0; i < size; ++i) bytes[i] = static_cast<unsigned char>(bits >> (8 * i));
  return bytes;
}

// The element's values in the binary_little_endian layout (what PointFile::element_values
// returns), or big-endian when `big_endian`.
inline std::vector<unsigned char> element_bytes(const Element& element, bool big_endian = false) {
  std::vector<unsigned char> out;
  for (const auto& row : element.rows) {
    std::size_t t = 0;
    const auto put = [&](const std::string& type) {
      std::vector<unsigned char> bytes = token_bytes(type, row.at(t++));
      if (big_endian) std::reverse(bytes.begin(), bytes.end());
      out.insert(out.end(), bytes.begin(), bytes.end());
    };
    for (const Column& column : element.columns) {
      if (column.count_type.empty()) {
        put(column.type);
        continue;
      }
      const long count = std::strtol(row.at(t).c_str(), nullptr, 10);
      put(column.count_type);
      for (long i = 0; i < count; ++i) put(column.type);
    }
  }
  return out;
}

inline std::string header_text(const PlyModel& model, Encoding encoding) {
  std::ostringstream text;
  text << "ply\nformat "
       << (encoding == Encoding::ascii           ? "ascii"
           : encoding == Encoding::little_endian ? "binary_little_endian"
                                                 : "binary_big_endian")
       << " 1.0\n";
  for (const std::string& comment : model.comments) text << comment << '\n';
  for (const Element& element : model.elements) {
    text << "element " << element.name << ' ' << element.rows.size() << '\n';
    for (const Column& column : element.columns) {
      text << "property ";
      if (!column.count_type.empty()) text << "list " << column.count_type << ' ';
      text << column.type << ' ' << column.name << '\n';
    }
  }
  text << "end_header\n";
  return text.str();
}

// The whole file, header in the style pnf writes (so that pnf's output can be compared byte
// for byte), ascii rows as single-space separated tokens.
inline std::string ply_text(const PlyModel& model, Encoding encoding) {
  std::string text = header_text(model, encoding);
  for (const Element& element : model.elements) {
    if (encoding == Encoding::ascii) {
      for (const auto& row : element.rows) {
        for (std::size_t t = 0; t < row.size(); ++t) text += (t ? " " : "") + row[t];
        text += '\n';
      }
    } else {
      const std::vector<unsigned char> bytes = element_bytes(element, encoding == Encoding::big_endian);
      text.append(bytes.begin(), bytes.end());
    }
  }
  return text;
}

inline void write_file(const std::filesystem::path& path, const std::string& contents) {
  std::ofstream out(path, std::ios::binary);
  out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
  ASSERT_TRUE(out.good()) << path;
}

inline std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace pnf::test
