// Reading the meshes of pnf_eval_real: ASCII OFF and PLY (real_meshes.hpp, read_mesh).
#include "real_meshes.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace pnf::eval {

namespace {

// Lines of a text file split into whitespace-separated tokens, with the 1-based line number for
// messages; blank lines and, where `comment` is set, text from that character on are skipped.
class LineReader {
 public:
  LineReader(const std::string& path, char comment) : path_(path), in_(path), comment_(comment) {
    if (!in_) throw std::runtime_error(path + ": cannot open the file");
  }
  // The next line with at least one token; false at the end of the file.
  bool next(std::vector<std::string>& tokens) {
    std::string line;
    while (std::getline(in_, line)) {
      ++line_;
      if (comment_ != 0) {
        const std::size_t at = line.find(comment_);
        if (at != std::string::npos) line.resize(at);
      }
      tokens.clear();
      std::istringstream words(line);
      std::string word;
      while (words >> word) tokens.push_back(word);
      if (!tokens.empty()) return true;
    }
    return false;
  }
  [[noreturn]] void fail(const std::string& message) const {
    throw std::runtime_error(path_ + ":" + std::to_string(line_) + ": " + message);
  }
  // The whole token as a finite double, or fail naming `what`.
  double number(const std::string& token, const char* what) const {
    errno = 0;
    char* end = nullptr;
    const double value = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != 0 || errno == ERANGE || !std::isfinite(value)) {
      fail(std::string("bad ") + what + " '" + token + "' (a finite number was expected)");
    }
    return value;
  }
  // The whole token as an integer in [0, limit), or fail naming `what`.
  std::size_t index(const std::string& token, std::size_t limit, const char* what) const {
    errno = 0;
    char* end = nullptr;
    const long long value = std::strtoll(token.c_str(), &end, 10);
    if (end == token.c_str() || *end != 0 || errno == ERANGE) {
      fail(std::string("bad ") + what + " '" + token + "' (an integer was expected)");
    }
    if (value < 0 || std::size_t(value) >= limit) {
      fail(std::string(what) + " " + token + " out of range (0 to " + std::to_string(limit) + " - 1)");
    }
    return std::size_t(value);
  }
  // Fails saying the file ended before `what`.
  [[noreturn]] void ended(const std::string& what) const {
    throw std::runtime_error(path_ + ":" + std::to_string(line_) + ": the file ends before " + what);
  }

 private:
  std::string path_;
  std::ifstream in_;
  char comment_;
  std::size_t line_ = 0;
};

// The polygon with corners `corners` as a fan of triangles from its first corner.
void add_fan(const std::vector<std::size_t>& corners, Mesh& mesh) {
  for (std::size_t i = 1; i + 1 < corners.size(); ++i) {
    mesh.triangles.push_back({corners[0], corners[i], corners[i + 1]});
  }
}

// A vertex/face count: a non-negative integer below 2^31 (pnf's point limit).
std::size_t count(const LineReader& reader, const std::string& token, const char* what) {
  return reader.index(token, std::size_t(1) << 31, what);
}

Mesh read_off(const std::string& path) {
  LineReader reader(path, '#');
  std::vector<std::string> tokens;
  if (!reader.next(tokens)) reader.ended("the OFF header");
  if (tokens[0] != "OFF") reader.fail("not an ASCII OFF file (the first word is '" + tokens[0] + "', not OFF)");
  tokens.erase(tokens.begin());
  if (tokens.empty() && !reader.next(tokens)) reader.ended("the vertex and face counts");
  if (tokens.size() < 2) reader.fail("expected the vertex and face counts 'V F [E]'");
  const std::size_t vertices = count(reader, tokens[0], "vertex count");
  const std::size_t faces = count(reader, tokens[1], "face count");
  Mesh mesh;
  mesh.vertices.reserve(vertices);
  for (std::size_t v = 0; v < vertices; ++v) {
    if (!reader.next(tokens)) reader.ended("vertex " + std::to_string(v) + " of " + std::to_string(vertices));
    if (tokens.size() < 3) reader.fail("vertex " + std::to_string(v) + ": expected x y z");
    mesh.vertices.push_back(
        {reader.number(tokens[0], "x"), reader.number(tokens[1], "y"), reader.number(tokens[2], "z")});
  }
  mesh.triangles.reserve(faces);
  std::vector<std::size_t> corners;
  for (std::size_t f = 0; f < faces; ++f) {
    if (!reader.next(tokens)) reader.ended("face " + std::to_string(f) + " of " + std::to_string(faces));
    const std::size_t n = count(reader, tokens[0], "face vertex count");
    if (n < 3) reader.fail("face " + std::to_string(f) + " has " + tokens[0] + " vertices (at least 3 expected)");
    if (tokens.size() < n + 1) reader.fail("face " + std::to_string(f) + ": expected " + tokens[0] + " vertex indices");
    corners.clear();
    for (std::size_t i = 0; i < n; ++i) corners.push_back(reader.index(tokens[1 + i], vertices, "vertex index"));
    add_fan(corners, mesh);
  }
  return mesh;
}

// One property of a PLY element: a scalar, or a list (its count read first, then that many items).
struct PlyProperty {
  std::string name;
  bool list = false;
};
struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
};

const char* const kPlyTypes[] = {"char", "uchar", "short", "ushort", "int",   "uint",   "float",   "double",
                                 "int8", "uint8", "int16", "uint16", "int32", "uint32", "float32", "float64"};
bool ply_type(const std::string& name) {
  return std::find(std::begin(kPlyTypes), std::end(kPlyTypes), name) != std::end(kPlyTypes);
}

Mesh read_ply(const std::string& path) {
  LineReader reader(path, 0);
  std::vector<std::string> tokens;
  if (!reader.next(tokens) || tokens[0] != "ply") reader.fail("not a PLY file (the first line is not 'ply')");
  if (!reader.next(tokens) || tokens[0] != "format") reader.fail("expected the 'format' line");
  if (tokens.size() < 2 || tokens[1] != "ascii") {
    reader.fail("only ASCII PLY is read here (format " + (tokens.size() > 1 ? tokens[1] : std::string("?")) + ")");
  }
  std::vector<PlyElement> elements;
  for (;;) {
    if (!reader.next(tokens)) reader.ended("end_header");
    if (tokens[0] == "end_header") break;
    if (tokens[0] == "comment" || tokens[0] == "obj_info") continue;
    if (tokens[0] == "element") {
      if (tokens.size() != 3) reader.fail("expected 'element NAME COUNT'");
      elements.push_back({tokens[1], count(reader, tokens[2], "element count"), {}});
    } else if (tokens[0] == "property") {
      if (elements.empty()) reader.fail("a property before any element");
      if (tokens.size() == 3 && ply_type(tokens[1])) {
        elements.back().properties.push_back({tokens[2], false});
      } else if (tokens.size() == 5 && tokens[1] == "list" && ply_type(tokens[2]) && ply_type(tokens[3])) {
        elements.back().properties.push_back({tokens[4], true});
      } else {
        reader.fail("expected 'property TYPE NAME' or 'property list TYPE TYPE NAME'");
      }
    } else {
      reader.fail("unknown header line '" + tokens[0] + "'");
    }
  }
  const auto vertex_element =
      std::find_if(elements.begin(), elements.end(), [](const PlyElement& e) { return e.name == "vertex"; });
  if (vertex_element == elements.end()) reader.fail("the header has no 'element vertex'");
  const auto face_element =
      std::find_if(elements.begin(), elements.end(), [](const PlyElement& e) { return e.name == "face"; });
  if (face_element == elements.end()) reader.fail("the header has no 'element face'");
  int xyz[3] = {-1, -1, -1};
  for (std::size_t p = 0; p < vertex_element->properties.size(); ++p) {
    const PlyProperty& prop = vertex_element->properties[p];
    for (int a = 0; a < 3; ++a) {
      if (prop.name == std::string(1, char('x' + a))) {
        if (prop.list) reader.fail("vertex property " + prop.name + " is a list");
        xyz[a] = int(p);
      }
    }
  }
  if (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0) reader.fail("the vertex element lacks x, y or z");
  int indices = -1;
  for (std::size_t p = 0; p < face_element->properties.size(); ++p) {
    const PlyProperty& prop = face_element->properties[p];
    if (prop.list && (prop.name == "vertex_indices" || prop.name == "vertex_index")) indices = int(p);
  }
  if (indices < 0) reader.fail("the face element has no 'property list ... vertex_indices'");

  Mesh mesh;
  mesh.vertices.reserve(vertex_element->count);
  std::vector<std::size_t> corners;
  for (const PlyElement& element : elements) {
    const bool is_vertex = &element == &*vertex_element, is_face = &element == &*face_element;
    if (is_face && mesh.vertices.size() != vertex_element->count) {
      reader.fail("the faces come before the vertices; read here only after them");
    }
    for (std::size_t row = 0; row < element.count; ++row) {
      if (!reader.next(tokens)) {
        reader.ended(element.name + " " + std::to_string(row) + " of " + std::to_string(element.count));
      }
      // Walk the properties: a scalar is one token, a list its count and then its items.
      std::size_t at = 0;
      Vec3 p{};
      corners.clear();
      for (std::size_t k = 0; k < element.properties.size(); ++k) {
        if (at >= tokens.size()) {
          reader.fail(element.name + " " + std::to_string(row) + ": too few values for its " +
                      std::to_string(element.properties.size()) + " properties");
        }
        if (!element.properties[k].list) {
          if (is_vertex) {
            for (int a = 0; a < 3; ++a) {
              if (int(k) == xyz[a]) p[a] = reader.number(tokens[at], element.properties[k].name.c_str());
            }
          }
          ++at;
          continue;
        }
        const std::size_t n = count(reader, tokens[at], "list length");
        ++at;
        if (at + n > tokens.size()) {
          reader.fail(element.name + " " + std::to_string(row) + ": the list " + element.properties[k].name +
                      " has fewer than " + std::to_string(n) + " items");
        }
        if (is_face && int(k) == indices) {
          if (n < 3) {
            reader.fail("face " + std::to_string(row) + " has " + std::to_string(n) +
                        " vertices (at least 3 expected)");
          }
          for (std::size_t i = 0; i < n; ++i) {
            corners.push_back(reader.index(tokens[at + i], vertex_element->count, "vertex index"));
          }
        }
        at += n;
      }
      if (at != tokens.size()) {
        reader.fail(element.name + " " + std::to_string(row) + ": " + std::to_string(tokens.size()) +
                    " values, its properties take " + std::to_string(at));
      }
      if (is_vertex) mesh.vertices.push_back(p);
      if (is_face) add_fan(corners, mesh);
    }
  }
  return mesh;
}

std::string lower_extension(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  return ext;
}

}  // namespace

Mesh read_mesh(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == "off") return read_off(path);
  if (ext == "ply") return read_ply(path);
  throw std::runtime_error(path + ": unknown mesh format '." + ext + "' (.off or ASCII .ply)");
}

}  // namespace pnf::eval
