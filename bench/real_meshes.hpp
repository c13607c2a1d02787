// Real shapes with known normals for pnf_eval_real: triangle meshes read from OFF or ASCII PLY
// (mesh_reader.cpp), scaled to a unit bounding-box diagonal and sampled uniformly by area, each
// sample carrying the mesh's true normal there (deterministic: the same mesh and seed, the same
// samples); and point sets whose files carry normals (read_point_set).
//
// The true normal (the definition the evaluation scores against):
//   - a triangle's corner normal at vertex v is the area-weighted average of the normals of the
//     triangles around v (vertices at identical positions count as one) whose normal is within
//     kCreaseAngleDeg (30 degrees) of the triangle's own normal, normalised: smooth across the
//     soft edges of a tessellated curved surface, sharp across creases;
//   - a sample's normal is the barycentric interpolation of its triangle's three corner normals,
//     normalised.
// Orientation: the faces are assumed consistently wound; when the mesh's signed volume is
// negative (wound inward) every normal is flipped. Degenerate triangles (zero area, see
// kDegenerateArea in the source) are never sampled and never enter a corner normal.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "eval_clouds.hpp"
#include "pnf/point_cloud.hpp"

namespace pnf::eval {

// Faces whose normals are within this angle (degrees) of a triangle's own share its corner
// normals; the usual crease angle of mesh viewers (smooth shading up to 30 degrees).
inline constexpr double kCreaseAngleDeg = 30;

// A triangle mesh: V vertices (model units), F triangles of vertex indices (0-based, each < V),
// counter-clockwise seen from outside when the mesh is wound outward.
struct Mesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::size_t, 3>> triangles;
};

// Reads a mesh by the file's extension (case-insensitive):
//   .off  ASCII OFF: "OFF" (the counts may follow on the same line), "V F E", V lines of x y z
//         (further columns ignored), F lines "n i0 .. i(n-1)" (further columns, e.g. colours,
//         ignored); polygons of n > 3 vertices are split into a fan of triangles. '#' starts a
//         comment.
//   .ply  ASCII PLY: an `element vertex` with float/double (or integer) properties among which
//         x, y, z (other properties read and ignored), and an `element face` whose first property
//         is `property list <count type> <index type> vertex_indices` (or vertex_index); other
//         elements, before or after, are skipped line by line; fans as for OFF.
// Throws std::runtime_error naming the file and the line for a missing file, a bad header, a
// short or malformed line, a non-finite coordinate, an index out of range, a face of fewer than 3
// vertices, or a file that ends early.
Mesh read_mesh(const std::string& path);

// Moves the centre of the bounding box to the origin and scales so that its diagonal is 1.
// Throws std::runtime_error for an empty mesh or one whose vertices all coincide.
void normalize_to_unit_diagonal(Mesh& mesh);
void normalize_to_unit_diagonal(std::vector<Vec3>& points);

// A point set whose file carries normals, taken as its truth (the held-out models: a scanned
// statue resampled with its mesh's normals, CGAL's example scans), read with pnf::read_point_file
// and scaled like a mesh (normalize_to_unit_diagonal); the normals made unit, area left 0. Throws
// pnf::Error for a bad file and std::runtime_error for one without normals.
Shape read_point_set(const std::string& path);

// The bounding-box diagonal of `points` (model units); 0 for none.
double bounding_box_diagonal(const std::vector<Vec3>& points);

// What the truth definition found in a mesh; per triangle t (F entries each).
struct MeshNormals {
  std::vector<Vec3> face_normals;                   // unit, oriented; zero for degenerate triangles
  std::vector<double> areas;                        // model units squared; 0 for degenerate triangles
  std::vector<std::array<Vec3, 3>> corner_normals;  // unit, oriented; zero for degenerate triangles
  double area = 0;                                  // total
  double signed_volume = 0;                         // as wound (before the flip), model units cubed
  bool flipped = false;                             // signed_volume < 0: every normal was flipped
  std::size_t degenerate = 0;                       // triangles of zero area
  std::size_t welded = 0;                           // vertices at the position of an earlier vertex
  // Edges (between welded vertices) by how many triangles use them, and edges that two triangles
  // traverse in the same direction (inconsistent winding there).
  std::size_t boundary_edges = 0, nonmanifold_edges = 0, misoriented_edges = 0;
  // Triangle corners where the 30-degree rule left out at least one face around the vertex: the
  // corners on creases.
  std::size_t sharp_corners = 0;
};

// The face and corner normals of `mesh` by the definition above (crease angle kCreaseAngleDeg
// unless given, degrees in (0, 180]). Throws std::runtime_error when every triangle is degenerate.
MeshNormals mesh_normals(const Mesh& mesh, double crease_angle_deg = kCreaseAngleDeg);

// The true normal at barycentric weights `weights` (on corners 0, 1, 2; non-negative, sum 1) of
// triangle `triangle` (< F, not degenerate): its corner normals interpolated, normalised.
Vec3 true_normal(const MeshNormals& normals, std::size_t triangle, const Vec3& weights);

// N samples uniformly by area (a triangle by its area, then a uniform point in it) with a
// std::mt19937_64 seeded by `seed`, each with its true normal (the corner normals interpolated at
// its barycentric coordinates, normalised) and the triangle it came from.
struct MeshSamples {
  Shape shape;                         // positions, normals (unit), area = the mesh's
  std::vector<std::size_t> triangles;  // N: the triangle of each sample
  std::vector<Vec3> barycentric;       // N: its weights on the triangle's corners 0, 1, 2
};
MeshSamples sample_mesh(const Mesh& mesh, const MeshNormals& normals, std::size_t points, std::uint64_t seed);

// The angles (degrees, 0..180) between oriented normals and the truth, over N pairs (N > 0):
// RMS and mean. Zero exactly when every normal has the direction of its truth.
struct AngleError {
  double rms_deg = 0, mean_deg = 0;
};
AngleError oriented_angle_error(const std::vector<Vec3>& normals, const std::vector<Vec3>& truth);

}  // namespace pnf::eval
