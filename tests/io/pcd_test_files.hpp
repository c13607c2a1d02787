// Hand-made PCD files for the tests: a header from its lines, bodies in each DATA kind built
// here independently of pnf's writer (ascii with printf, binary_compressed as an LZF stream of
// literal runs, the simplest valid LZF).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace pnf::test {

// One field of a hand-made PCD: name, TYPE, SIZE, COUNT.
struct TestField {
  std::string name;
  char type;
  unsigned size;
  std::size_t count;
};

inline std::size_t test_point_bytes(const std::vector<TestField>& fields, bool with_padding = true) {
  std::size_t bytes = 0;
  for (const TestField& f : fields) {
    if (with_padding || f.name != "_") bytes += f.size * f.count;
  }
  return bytes;
}

// The header lines FIELDS .. DATA for `fields`.
inline std::string test_pcd_header(const std::vector<TestField>& fields, std::size_t width, std::size_t height,
                                   const std::string& data, const std::string& viewpoint = "0 0 0 1 0 0 0") {
  std::string names, sizes, types, counts;
  for (const TestField& f : fields) {
    names += " " + f.name;
    sizes += " " + std::to_string(f.size);
    types += std::string(" ") + f.type;
    counts += " " + std::to_string(f.count);
  }
  return "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS" + names + "\nSIZE" + sizes + "\nTYPE" +
         types + "\nCOUNT" + counts + "\nWIDTH " + std::to_string(width) + "\nHEIGHT " + std::to_string(height) +
         "\nVIEWPOINT " + viewpoint + "\nPOINTS " + std::to_string(width * height) + "\nDATA " + data + "\n";
}

// An LZF stream that decodes to `bytes`: literal runs of up to 32 bytes, each after a control
// byte holding its length - 1.
inline std::string lzf_literals(const std::string& bytes) {
  std::string out;
  for (std::size_t at = 0; at < bytes.size(); at += 32) {
    const std::size_t run = std::min<std::size_t>(32, bytes.size() - at);
    out += static_cast<char>(run - 1);
    out += bytes.substr(at, run);
  }
  return out;
}

inline std::string u32_le(std::uint32_t value) {
  std::string out(4, '\0');
  for (int b = 0; b < 4; ++b) out[b] = static_cast<char>(value >> (8 * b));
  return out;
}

// The binary_compressed body of `rows` (binary layout): the fields' columns in turn, padding
// left out, as an LZF stream after its two sizes.
inline std::string test_compressed_body(const std::vector<TestField>& fields, const std::string& rows) {
  const std::size_t point_bytes = test_point_bytes(fields);
  const std::size_t points = rows.size() / point_bytes;
  std::string packed;
  std::size_t column = 0;
  for (const TestField& f : fields) {
    const std::size_t bytes = f.size * f.count;
    if (f.name != "_") {
      for (std::size_t p = 0; p < points; ++p) packed += rows.substr(p * point_bytes + column, bytes);
    }
    column += bytes;
  }
  const std::string lzf = lzf_literals(packed);
  return u32_le(static_cast<std::uint32_t>(lzf.size())) + u32_le(static_cast<std::uint32_t>(packed.size())) + lzf;
}

// The ascii body of `rows`: every value in its type, floats with enough digits to read back
// exactly (%.9g, %.17g), padding fields left out unless `with_padding`.
inline std::string test_ascii_body(const std::vector<TestField>& fields, const std::string& rows,
                                   bool with_padding = false) {
  const std::size_t point_bytes = test_point_bytes(fields);
  std::string text;
  for (std::size_t p = 0; p * point_bytes < rows.size(); ++p) {
    const char* at = rows.data() + p * point_bytes;
    std::string line;
    for (const TestField& f : fields) {
      for (std::size_t i = 0; i < f.count; ++i, at += f.size) {
        if (f.name == "_" && !with_padding) continue;
        char buffer[64];
        if (f.type == 'F' && f.size == 4) {
          float v;
          std::memcpy(&v, at, 4);
          std::snprintf(buffer, sizeof buffer, "%.9g", double(v));
        } else if (f.type == 'F') {
          double v;
          std::memcpy(&v, at, 8);
          std::snprintf(buffer, sizeof buffer, "%.17g", v);
        } else if (f.type == 'U') {
          std::uint64_t v = 0;
          std::memcpy(&v, at, f.size);
          std::snprintf(buffer, sizeof buffer, "%llu", static_cast<unsigned long long>(v));
        } else {
          std::int64_t v = 0;
          std::memcpy(&v, at, f.size);
          const int shift = 64 - 8 * int(f.size);  // sign-extend
          v = static_cast<std::int64_t>(static_cast<std::uint64_t>(v) << shift) >> shift;
          std::snprintf(buffer, sizeof buffer, "%lld", static_cast<long long>(v));
        }
        line += (line.empty() ? "" : " ") + std::string(buffer);
      }
    }
    text += line + "\n";
  }
  return text;
}

inline std::string float_bytes(float value) { return std::string(reinterpret_cast<const char*>(&value), 4); }

// The DATA section of a PCD file for `rows` (packed binary rows of `fields`) in the DATA kind
// `data` names: ascii, binary (the rows themselves) or binary_compressed.
inline std::string test_body(const std::string& data, const std::vector<TestField>& fields, const std::string& rows) {
  if (data == "ascii") return test_ascii_body(fields, rows);
  if (data == "binary_compressed") return test_compressed_body(fields, rows);
  return rows;
}

}  // namespace pnf::test
