// Meshes with known normals for pnf_eval_real (real_meshes.hpp): the truth, the samples, the score.
// Reading them: mesh_reader.cpp.
#include "real_meshes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <tuple>

#include "geometry.hpp"
#include "pnf/point_file.hpp"

namespace pnf::eval {

namespace {

using geometry::kPi;

// A triangle is degenerate (zero area, its normal undefined) when |e1 x e2| is at most this
// share of its longest edge squared: the sine of its largest angle under 1e-12, which is rounding
// of exactly collinear corners in double, far below anything float coordinates in a text file can
// make on purpose (their own rounding is 1e-7 relative).
constexpr double kDegenerateArea = 1e-12;

Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }

}  // namespace

double bounding_box_diagonal(const std::vector<Vec3>& points) {
  if (points.empty()) return 0;
  Vec3 low = points[0], high = points[0];
  for (const Vec3& p : points) {
    for (int a = 0; a < 3; ++a) low[a] = std::min(low[a], p[a]), high[a] = std::max(high[a], p[a]);
  }
  return geometry::norm(sub(high, low));
}

void normalize_to_unit_diagonal(std::vector<Vec3>& points) {
  if (points.empty()) throw std::runtime_error("normalize_to_unit_diagonal: no points");
  Vec3 low = points[0], high = points[0];
  for (const Vec3& p : points) {
    for (int a = 0; a < 3; ++a) low[a] = std::min(low[a], p[a]), high[a] = std::max(high[a], p[a]);
  }
  const double diagonal = geometry::norm(sub(high, low));
  if (!(diagonal > 0) || !std::isfinite(diagonal)) {
    throw std::runtime_error("normalize_to_unit_diagonal: the points all coincide");
  }
  const Vec3 centre = scale(add(low, high), 0.5);
  for (Vec3& p : points) p = scale(sub(p, centre), 1 / diagonal);
}

void normalize_to_unit_diagonal(Mesh& mesh) { normalize_to_unit_diagonal(mesh.vertices); }

Shape read_point_set(const std::string& path) {
  const PointCloud cloud = read_point_file(path).cloud();
  if (cloud.normals.size() != cloud.positions.size()) {
    throw std::runtime_error(path + ": the point set carries no normals to take as the truth");
  }
  Shape shape;
  shape.positions = cloud.positions;
  normalize_to_unit_diagonal(shape.positions);
  shape.normals.reserve(cloud.normals.size());
  for (const Vec3& n : cloud.normals) shape.normals.push_back(scale(n, 1 / geometry::norm(n)));
  return shape;
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
