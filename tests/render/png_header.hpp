// Reading back what write_png wrote, without libpng: the chunk layout of a PNG file (signature,
// IHDR first, IEND last) and the IHDR fields. Enough to check size and format; the pixels are
// checked on the Image before encoding.
#pragma once

#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace pnf::render_test {

struct PngHeader {
  bool valid = false;  // signature, IHDR first and IEND last all present
  std::uint32_t width = 0, height = 0;
  int bit_depth = 0, colour_type = 0;  // 8 and 2 (RGB) for write_png
  std::size_t idat_chunks = 0;
};

inline std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

inline std::uint32_t big_endian32(const std::string& bytes, std::size_t at) {
  return std::uint32_t(std::uint8_t(bytes[at])) << 24 | std::uint32_t(std::uint8_t(bytes[at + 1])) << 16 |
         std::uint32_t(std::uint8_t(bytes[at + 2])) << 8 | std::uint32_t(std::uint8_t(bytes[at + 3]));
}

inline PngHeader read_png_header(const std::string& path) {
  static const std::string kSignature = "\x89PNG\r\n\x1a\n";
  const std::string bytes = read_bytes(path);
  PngHeader header;
  if (bytes.compare(0, kSignature.size(), kSignature) != 0) return header;
  std::size_t at = kSignature.size();
  std::vector<std::string> types;
  while (at + 12 <= bytes.size()) {
    const std::uint32_t length = big_endian32(bytes, at);
    const std::string type = bytes.substr(at + 4, 4);
    if (at + 12 + length > bytes.size()) return header;
    if (type == "IHDR" && length == 13) {
      header.width = big_endian32(bytes, at + 8);
      header.height = big_endian32(bytes, at + 12);
      header.bit_depth = std::uint8_t(bytes[at + 16]);
      header.colour_type = std::uint8_t(bytes[at + 17]);
    }
    if (type == "IDAT") ++header.idat_chunks;
    types.push_back(type);
    at += 12 + length;  // length, type, data, CRC
  }
  header.valid = at == bytes.size() && !types.empty() && types.front() == "IHDR" && types.back() == "IEND" &&
                 header.idat_chunks > 0;
  return header;
}

}  // namespace pnf::render_test
