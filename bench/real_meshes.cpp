// Meshes with known normals for pnf_eval_real (real_meshes.hpp).
#include "real_meshes.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "geometry.hpp"

namespace pnf::eval {

namespace {

using geometry::kPi;

// A triangle is degenerate (zero area, its normal undefined) when |e1 x e2| is at most this
// share of its longest edge squared: the sine of its largest angle under 1e-12, which is rounding
// of exactly collinear corners in double, far below anything float coordinates in a text file can
// make on purpose (their own rounding is 1e-7 relative).
constexpr double kDegenerateArea = 1e-12;

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

Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }

}  // namespace

Mesh read_mesh(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == "off") return read_off(path);
  if (ext == "ply") return read_ply(path);
  throw std::runtime_error(path + ": unknown mesh format '." + ext + "' (.off or ASCII .ply)");
}

double bounding_box_diagonal(const std::vector<Vec3>& points) {
  if (points.empty()) return 0;
  Vec3 low = points[0], high = points[0];
  for (const Vec3& p : points) {
    for (int a = 0; a < 3; ++a) low[a] = std::min(low[a], p[a]), high[a] = std::max(high[a], p[a]);
  }
  return geometry::norm(sub(high, low));
}

void normalize_to_unit_diagonal(Mesh& mesh) {
  if (mesh.vertices.empty()) throw std::runtime_error("normalize_to_unit_diagonal: the mesh has no vertices");
  Vec3 low = mesh.vertices[0], high = mesh.vertices[0];
  for (const Vec3& p : mesh.vertices) {
    for (int a = 0; a < 3; ++a) low[a] = std::min(low[a], p[a]), high[a] = std::max(high[a], p[a]);
  }
  const double diagonal = geometry::norm(sub(high, low));
  if (!(diagonal > 0) || !std::isfinite(diagonal)) {
    throw std::runtime_error("normalize_to_unit_diagonal: the vertices all coincide");
  }
  const Vec3 centre = scale(add(low, high), 0.5);
  for (Vec3& p : mesh.vertices) p = scale(sub(p, centre), 1 / diagonal);
}

MeshNormals mesh_normals(const Mesh& mesh, double crease_angle_deg) {
  if (!(crease_angle_deg > 0 && crease_angle_deg <= 180)) {
    throw std::runtime_error("mesh_normals: crease angle " + std::to_string(crease_angle_deg) +
                             " outside (0, 180] degrees");
  }
  const std::size_t vertex_count = mesh.vertices.size(), triangle_count = mesh.triangles.size();
  MeshNormals out;
  // Welding: each vertex stands for the first vertex at exactly its position, so that a mesh
  // split along its seams (one vertex per face corner) is still smooth across them.
  std::vector<std::size_t> order(vertex_count), canonical(vertex_count);
  for (std::size_t v = 0; v < vertex_count; ++v) order[v] = v;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::tie(mesh.vertices[a][0], mesh.vertices[a][1], mesh.vertices[a][2], a) <
           std::tie(mesh.vertices[b][0], mesh.vertices[b][1], mesh.vertices[b][2], b);
  });
  for (std::size_t i = 0; i < vertex_count; ++i) {
    const std::size_t v = order[i];
    if (i > 0 && mesh.vertices[v] == mesh.vertices[order[i - 1]]) {
      canonical[v] = canonical[order[i - 1]];
      ++out.welded;
    } else {
      canonical[v] = v;
    }
  }

  out.face_normals.assign(triangle_count, Vec3{0, 0, 0});
  out.areas.assign(triangle_count, 0);
  out.corner_normals.assign(triangle_count, {Vec3{0, 0, 0}, Vec3{0, 0, 0}, Vec3{0, 0, 0}});
  for (std::size_t t = 0; t < triangle_count; ++t) {
    const auto& tri = mesh.triangles[t];
    const Vec3 &a = mesh.vertices[tri[0]], &b = mesh.vertices[tri[1]], &c = mesh.vertices[tri[2]];
    const Vec3 ab = sub(b, a), ac = sub(c, a), bc = sub(c, b);
    const Vec3 twice_area = geometry::cross(ab, ac);
    out.signed_volume += dot(a, geometry::cross(b, c)) / 6;
    const double longest = std::max({dot(ab, ab), dot(ac, ac), dot(bc, bc)});
    const double length = geometry::norm(twice_area);
    if (!(length > kDegenerateArea * longest)) {
      ++out.degenerate;
      continue;
    }
    out.areas[t] = length / 2;
    out.area += out.areas[t];
    out.face_normals[t] = scale(twice_area, 1 / length);
  }
  if (out.degenerate == triangle_count) throw std::runtime_error("mesh_normals: every triangle is degenerate");
  out.flipped = out.signed_volume < 0;
  if (out.flipped) {
    for (Vec3& n : out.face_normals) n = scale(n, -1);
  }

  // The triangles around each (welded) vertex, degenerate ones left out: CSR.
  std::vector<std::size_t> start(vertex_count + 1, 0), around;
  for (std::size_t t = 0; t < triangle_count; ++t) {
    if (out.areas[t] == 0) continue;
    for (std::size_t v : mesh.triangles[t]) ++start[canonical[v] + 1];
  }
  for (std::size_t v = 0; v < vertex_count; ++v) start[v + 1] += start[v];
  around.resize(start[vertex_count]);
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (std::size_t t = 0; t < triangle_count; ++t) {
    if (out.areas[t] == 0) continue;
    for (std::size_t v : mesh.triangles[t]) around[fill[canonical[v]]++] = t;
  }

  const double min_cos = std::cos(crease_angle_deg * kPi / 180);
  for (std::size_t t = 0; t < triangle_count; ++t) {
    if (out.areas[t] == 0) continue;
    const Vec3& own = out.face_normals[t];
    for (int k = 0; k < 3; ++k) {
      const std::size_t v = canonical[mesh.triangles[t][k]];
      Vec3 sum{0, 0, 0};
      bool left_out = false;
      for (std::size_t i = start[v]; i < start[v + 1]; ++i) {
        const std::size_t f = around[i];
        if (dot(out.face_normals[f], own) >= min_cos) {
          sum = add(sum, scale(out.face_normals[f], out.areas[f]));
        } else {
          left_out = true;
        }
      }
      // t itself is in the sum, and below a crease angle of 90 degrees every term is within 90
      // degrees of it, so the sum is not zero; above, faces may cancel: then t's own normal.
      out.corner_normals[t][k] = geometry::norm(sum) > 0 ? geometry::normalized(sum) : own;
      if (left_out) ++out.sharp_corners;
    }
  }

  // Edges between welded vertices: how many triangles use each, and in which direction.
  struct Edge {
    std::size_t low, high;
    bool forward;  // traversed low -> high
  };
  std::vector<Edge> edges;
  edges.reserve(3 * triangle_count);
  for (const auto& tri : mesh.triangles) {
    const std::size_t c[3] = {canonical[tri[0]], canonical[tri[1]], canonical[tri[2]]};
    if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;
    for (int k = 0; k < 3; ++k) {
      const std::size_t from = c[k], to = c[(k + 1) % 3];
      edges.push_back({std::min(from, to), std::max(from, to), from < to});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) {
    return std::tie(a.low, a.high, a.forward) < std::tie(b.low, b.high, b.forward);
  });
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].low == edges[i].low && edges[j].high == edges[i].high) ++j;
    const std::size_t uses = j - i;
    if (uses == 1) ++out.boundary_edges;
    if (uses > 2) ++out.nonmanifold_edges;
    if (uses == 2 && edges[i].forward == edges[i + 1].forward) ++out.misoriented_edges;
    i = j;
  }
  return out;
}

Vec3 true_normal(const MeshNormals& normals, std::size_t triangle, const Vec3& weights) {
  const auto& corner = normals.corner_normals[triangle];
  Vec3 n{0, 0, 0};
  for (int k = 0; k < 3; ++k) n = add(n, scale(corner[k], weights[k]));
  // At a crease angle of 30 degrees the corners are within 60 degrees of one another and n is far
  // from zero; with wider ones they may cancel: then the face's own normal.
  return geometry::norm(n) > 0 ? geometry::normalized(n) : normals.face_normals[triangle];
}

MeshSamples sample_mesh(const Mesh& mesh, const MeshNormals& normals, std::size_t points, std::uint64_t seed) {
  if (normals.areas.size() != mesh.triangles.size()) {
    throw std::runtime_error("sample_mesh: normals of " + std::to_string(normals.areas.size()) +
                             " triangles for a mesh of " + std::to_string(mesh.triangles.size()));
  }
  std::mt19937_64 rng(seed);
  std::discrete_distribution<std::size_t> pick(normals.areas.begin(), normals.areas.end());
  std::uniform_real_distribution<double> u01(0, 1);
  MeshSamples out;
  out.shape.area = normals.area;
  out.shape.positions.reserve(points);
  out.shape.normals.reserve(points);
  out.triangles.reserve(points);
  out.barycentric.reserve(points);
  for (std::size_t i = 0; i < points; ++i) {
    const std::size_t t = pick(rng);
    // Uniform over the triangle: the square-root map of the unit square onto barycentric weights.
    const double r = std::sqrt(u01(rng)), s = u01(rng);
    const Vec3 w = {1 - r, r * (1 - s), r * s};
    const auto& tri = mesh.triangles[t];
    Vec3 p{0, 0, 0};
    for (int k = 0; k < 3; ++k) p = add(p, scale(mesh.vertices[tri[k]], w[k]));
    out.shape.positions.push_back(p);
    out.shape.normals.push_back(true_normal(normals, t, w));
    out.triangles.push_back(t);
    out.barycentric.push_back(w);
  }
  return out;
}

AngleError oriented_angle_error(const std::vector<Vec3>& normals, const std::vector<Vec3>& truth) {
  if (normals.empty() || normals.size() != truth.size()) {
    throw std::runtime_error("oriented_angle_error: " + std::to_string(normals.size()) + " normals against " +
                             std::to_string(truth.size()) + " true ones (equal and > 0 expected)");
  }
  double sum = 0, sum_squares = 0;
  for (std::size_t i = 0; i < normals.size(); ++i) {
    const double t = geometry::angle_degrees(normals[i], truth[i]);
    sum += t;
    sum_squares += t * t;
  }
  const double n = double(normals.size());
  return {std::sqrt(sum_squares / n), sum / n};
}

}  // namespace pnf::eval
