// The truth of pnf_eval_real (bench/real_meshes.hpp): meshes read, scaled to a unit diagonal and
// sampled by area, each sample's true normal the corner normals (smooth below a 30-degree
// crease, sharp above) interpolated. Synthetic meshes check the definition against answers worked
// out by hand; the team's shared meshes (skipped when ../shared/data is absent) that the reading,
// scaling and orientation hold on the real files. The readers: mesh_reader_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "geometry.hpp"
#include "real_meshes.hpp"
#include "test_clouds.hpp"

namespace pnf::test {
namespace {

using eval::Mesh;
using eval::MeshNormals;
using eval::MeshSamples;
using geometry::angle_degrees;
using geometry::kPi;

// Angles that must be equal up to double rounding (degrees): atan2-based angles of vectors built
// from a few products and sums are exact to about 1e-14 radians.
constexpr double kSameDirectionDeg = 1e-9;

Vec3 face_normal(const Mesh& m, std::size_t t) {
  const auto& tri = m.triangles[t];
  const Vec3 a = m.vertices[tri[0]], b = m.vertices[tri[1]], c = m.vertices[tri[2]];
  return geometry::normalized(
      geometry::cross({b[0] - a[0], b[1] - a[1], b[2] - a[2]}, {c[0] - a[0], c[1] - a[1], c[2] - a[2]}));
}

Vec3 negated(const Vec3& v) { return {-v[0], -v[1], -v[2]}; }

// Two unit squares sharing the edge x = 0, 0 <= y <= 1: A in the plane z = 0 (x from -1 to 0),
// B leaving the edge in the direction (cos a, 0, sin a). Wound consistently, A's normal is
// (0, 0, 1) and B's (-sin a, 0, cos a): the normals are `a` degrees apart (a dihedral angle of
// 180 - a). Two triangles each: A = {0, 1, 2}, {0, 2, 3}; B = {1, 4, 5}, {1, 5, 2}.
Mesh hinge(double a_degrees) {
  const double a = a_degrees * kPi / 180;
  Mesh m;
  m.vertices = {
      {-1, 0, 0}, {0, 0, 0}, {0, 1, 0}, {-1, 1, 0}, {std::cos(a), 0, std::sin(a)}, {std::cos(a), 1, std::sin(a)}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}, {1, 4, 5}, {1, 5, 2}};
  return m;
}

// The unit cube [0, 1]^3, wound outward (or inward).
Mesh cube(bool inward) {
  Mesh m;
  for (int i = 0; i < 8; ++i) m.vertices.push_back({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
  // Each face as a quad counter-clockwise seen from outside.
  const std::size_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  if (inward) {
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
  }
  return m;
}

// An icosahedron subdivided `levels` times (each triangle into 4), vertices on the unit sphere,
// wound outward.
Mesh icosphere(int levels) {
  const double g = (1 + std::sqrt(5.0)) / 2;
  Mesh m;
  m.vertices = {{-1, g, 0},  {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g},  {0, 1, g},
                {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
  m.triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (Vec3& v : m.vertices) v = geometry::normalized(v);
  for (int level = 0; level < levels; ++level) {
    std::vector<std::array<std::size_t, 3>> finer;
    std::map<std::pair<std::size_t, std::size_t>, std::size_t> middle;
    auto mid = [&](std::size_t a, std::size_t b) {
      const auto key = std::minmax(a, b);
      const auto it = middle.find(key);
      if (it != middle.end()) return it->second;
      const Vec3& p = m.vertices[a];
      const Vec3& q = m.vertices[b];
      m.vertices.push_back(geometry::normalized({p[0] + q[0], p[1] + q[1], p[2] + q[2]}));
      return middle[key] = m.vertices.size() - 1;
    };
    for (const auto& t : m.triangles) {
      const std::size_t ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
      finer.push_back({t[0], ab, ca});
      finer.push_back({t[1], bc, ab});
      finer.push_back({t[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    m.triangles = finer;
  }
  return m;
}

TEST(RealMeshes, NinetyDegreeCreaseIsSharp) {
  const Mesh m = hinge(90);
  const MeshNormals normals = eval::mesh_normals(m);
  const MeshSamples s = eval::sample_mesh(m, normals, 4000, 7);
  // One orientation for both faces (the signed volume of an open hinge decides which).
  const double side = normals.flipped ? -1 : 1;
  const Vec3 a = {0, 0, side}, b = {-side, 0, 0};
  std::size_t on_a = 0;
  for (std::size_t i = 0; i < s.triangles.size(); ++i) {
    const bool is_a = s.triangles[i] < 2;
    on_a += is_a;
    ASSERT_LT(angle_degrees(s.shape.normals[i], is_a ? a : b), kSameDirectionDeg)
        << "sample " << i << " on triangle " << s.triangles[i];
  }
  // Both faces sampled, in proportion to their (equal) areas: 2000 expected, sd 32.
  EXPECT_NEAR(double(on_a), 2000, 150);
  EXPECT_EQ(normals.sharp_corners, 6u);  // the crease's two vertices, in each of the 3 triangles at each
}

TEST(RealMeshes, SoftEdgeIsSmoothAndAreaWeighted) {
  // Normals 20 degrees apart: within 30, so the corners on the shared edge average both faces,
  // each face weighted by its area. Vertex 1 = (0, 0, 0) has A's triangle {0, 1, 2} (area 1/2)
  // and both of B's (1/2 each): corner normal along nA + 2 nB.
  const Mesh m = hinge(20);
  const MeshNormals normals = eval::mesh_normals(m);
  const double side = normals.flipped ? -1 : 1;
  const double a = 20 * kPi / 180;
  const Vec3 na = {0, 0, side}, nb = {-side * std::sin(a), 0, side * std::cos(a)};
  const Vec3 expected = geometry::normalized({na[0] + 2 * nb[0], na[1] + 2 * nb[1], na[2] + 2 * nb[2]});
  EXPECT_LT(angle_degrees(eval::true_normal(normals, 0, {0, 1, 0}), expected), kSameDirectionDeg);
  EXPECT_LT(angle_degrees(eval::true_normal(normals, 2, {1, 0, 0}), expected), kSameDirectionDeg);
  // Away from the edge (vertex 0 = (-1, 0, 0), only on A) the face's own normal.
  EXPECT_LT(angle_degrees(eval::true_normal(normals, 0, {1, 0, 0}), na), kSameDirectionDeg);
  EXPECT_EQ(normals.sharp_corners, 0u);
  // The samples turn continuously between the faces: every one between nA and nB, and some
  // well inside that range.
  const MeshSamples s = eval::sample_mesh(m, normals, 4000, 8);
  double widest = 0;
  for (std::size_t i = 0; i < s.triangles.size(); ++i) {
    const Vec3& n = s.shape.normals[i];
    ASSERT_NEAR(angle_degrees(n, na) + angle_degrees(n, nb), 20, 1e-9) << "sample " << i;
    widest = std::max(widest, std::min(angle_degrees(n, na), angle_degrees(n, nb)));
  }
  EXPECT_GT(widest, 5);
}

TEST(RealMeshes, FortyDegreeCreaseIsSharp) {
  const Mesh m = hinge(40);
  const MeshNormals normals = eval::mesh_normals(m);
  const double side = normals.flipped ? -1 : 1;
  const double a = 40 * kPi / 180;
  const Vec3 na = {0, 0, side}, nb = {-side * std::sin(a), 0, side * std::cos(a)};
  EXPECT_LT(angle_degrees(eval::true_normal(normals, 0, {0, 1, 0}), na), kSameDirectionDeg);
  EXPECT_LT(angle_degrees(eval::true_normal(normals, 2, {1, 0, 0}), nb), kSameDirectionDeg);
}

TEST(RealMeshes, CubeNormalsPointOutwardWhateverTheWinding) {
  for (const bool inward : {false, true}) {
    SCOPED_TRACE(inward ? "wound inward" : "wound outward");
    const Mesh m = cube(inward);
    const MeshNormals normals = eval::mesh_normals(m);
    EXPECT_EQ(normals.flipped, inward);
    EXPECT_NEAR(std::fabs(normals.signed_volume), 1, 1e-12);
    EXPECT_EQ(normals.boundary_edges, 0u);
    EXPECT_EQ(normals.misoriented_edges, 0u);
    const MeshSamples s = eval::sample_mesh(m, normals, 3000, 9);
    for (std::size_t i = 0; i < s.triangles.size(); ++i) {
      // Outward: the axis the sample sits on the face of, towards that face.
      const Vec3& p = s.shape.positions[i];
      Vec3 out{0, 0, 0};
      for (int axis = 0; axis < 3; ++axis) {
        if (p[axis] < 1e-12 || p[axis] > 1 - 1e-12) out[axis] = p[axis] < 0.5 ? -1 : 1;
      }
      // A sample on an edge of the cube would be on two faces; area sampling never lands there.
      ASSERT_EQ(std::fabs(out[0]) + std::fabs(out[1]) + std::fabs(out[2]), 1) << "sample " << i;
      ASSERT_LT(angle_degrees(s.shape.normals[i], out), kSameDirectionDeg) << "sample " << i;
    }
  }
}

TEST(RealMeshes, MisorientedFacesAreCounted) {
  Mesh m = cube(false);
  std::swap(m.triangles[0][1], m.triangles[0][2]);  // one triangle wound the other way
  EXPECT_EQ(eval::mesh_normals(m).misoriented_edges, 3u);
}

TEST(RealMeshes, FineSphereIsSmooth) {
  // Level 3: 1280 triangles, neighbouring faces about 8 degrees apart. Face normals are up to
  // about 4 degrees from the radial direction at the corners, so a rule that kept the faces
  // sharp fails the 1-degree bound; the smoothed corners are within 0.2 degrees.
  const Mesh m = icosphere(3);
  const MeshNormals normals = eval::mesh_normals(m);
  EXPECT_FALSE(normals.flipped);
  EXPECT_EQ(normals.sharp_corners, 0u);
  const MeshSamples s = eval::sample_mesh(m, normals, 20000, 10);
  double worst = 0, worst_face = 0;
  for (std::size_t i = 0; i < s.triangles.size(); ++i) {
    worst = std::max(worst, angle_degrees(s.shape.normals[i], s.shape.positions[i]));
    worst_face = std::max(worst_face, angle_degrees(normals.face_normals[s.triangles[i]], s.shape.positions[i]));
  }
  EXPECT_LT(worst, 1);
  EXPECT_GT(worst_face, 2);  // the test can tell the rules apart
}

TEST(RealMeshes, DegenerateTrianglesAreNeverSampled) {
  Mesh m = hinge(90);
  m.vertices.push_back({0, 0.5, 0});  // on the crease, between vertices 1 and 2
  m.triangles.push_back({1, 6, 2});   // collinear: zero area
  const MeshNormals normals = eval::mesh_normals(m);
  EXPECT_EQ(normals.degenerate, 1u);
  EXPECT_EQ(normals.areas[4], 0);
  EXPECT_NEAR(normals.area, 2, 1e-12);
  const MeshSamples s = eval::sample_mesh(m, normals, 2000, 11);
  EXPECT_EQ(std::count(s.triangles.begin(), s.triangles.end(), std::size_t(4)), 0);
  // The crease stays sharp: the degenerate triangle took part in no corner normal.
  EXPECT_LT(angle_degrees(eval::true_normal(normals, 0, {0, 1, 0}), {0, 0, normals.flipped ? -1.0 : 1.0}),
            kSameDirectionDeg);
}

TEST(RealMeshes, SamplingIsDeterministicAndUniformByArea) {
  // Two triangles of areas 1/2 and 3/2 (quarter and three quarters of the samples).
  Mesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {4, 0, 0}, {4, 1, 0}};
  m.triangles = {{0, 1, 2}, {1, 3, 4}};
  const MeshNormals normals = eval::mesh_normals(m);
  const MeshSamples a = eval::sample_mesh(m, normals, 8000, 12), b = eval::sample_mesh(m, normals, 8000, 12);
  const MeshSamples c = eval::sample_mesh(m, normals, 8000, 13);
  EXPECT_EQ(a.shape.positions, b.shape.positions);
  EXPECT_EQ(a.shape.normals, b.shape.normals);
  EXPECT_NE(a.shape.positions, c.shape.positions);
  // 2000 expected on the small one, standard deviation 39.
  EXPECT_NEAR(double(std::count(a.triangles.begin(), a.triangles.end(), std::size_t(0))), 2000, 200);
  // Uniform inside a triangle: the mean of the samples on the small one is its centroid (1/3, 1/3)
  // (standard deviation of the mean about 0.005).
  double x = 0, y = 0, n = 0;
  for (std::size_t i = 0; i < a.triangles.size(); ++i) {
    if (a.triangles[i] != 0) continue;
    x += a.shape.positions[i][0], y += a.shape.positions[i][1], n += 1;
  }
  EXPECT_NEAR(x / n, 1.0 / 3, 0.02);
  EXPECT_NEAR(y / n, 1.0 / 3, 0.02);
}

TEST(RealMeshes, ScalingGivesUnitDiagonalCentred) {
  Mesh m = cube(false);
  for (Vec3& v : m.vertices) v = {2 + 3 * v[0], -1 + 4 * v[1], 10 * v[2]};  // a 3 x 4 x 10 box
  eval::normalize_to_unit_diagonal(m);
  EXPECT_NEAR(eval::bounding_box_diagonal(m.vertices), 1, 1e-15);
  const double d = std::sqrt(9.0 + 16 + 100);
  EXPECT_NEAR(m.vertices[0][0], -1.5 / d, 1e-15);
  EXPECT_NEAR(m.vertices[7][2], 5 / d, 1e-15);
  const MeshNormals normals = eval::mesh_normals(m);
  const MeshSamples s = eval::sample_mesh(m, normals, 5000, 14);
  const double sampled = eval::bounding_box_diagonal(s.shape.positions);
  EXPECT_LE(sampled, 1 + 1e-12);
  EXPECT_GT(sampled, 0.97);
}

TEST(RealMeshes, ExactInputHasNoError) {
  const Mesh m = icosphere(2);
  const MeshSamples s = eval::sample_mesh(m, eval::mesh_normals(m), 1000, 15);
  const eval::AngleError e = eval::oriented_angle_error(s.shape.normals, s.shape.normals);
  EXPECT_EQ(e.rms_deg, 0);
  EXPECT_EQ(e.mean_deg, 0);
  // Oriented: the opposite normals are 180 degrees off, not 0 as lines would be.
  std::vector<Vec3> flipped;
  for (const Vec3& n : s.shape.normals) flipped.push_back(negated(n));
  EXPECT_NEAR(eval::oriented_angle_error(flipped, s.shape.normals).mean_deg, 180, 1e-9);
}

// The team's meshes (../shared/data), as pnf_eval_real reads them.
struct SharedMesh {
  const char* file;
  bool cad;
};
const SharedMesh kSharedMeshes[] = {{"meshes/casting.off", true},
                                    {"meshes/crank.off", true},
                                    {"meshes/cup.off", true},
                                    {"fandisk.off", true},
                                    {"meshes/camel.off", false},
                                    {"meshes/teddy.off", false},
                                    {"meshes/seahorse2_100K.off", false},
                                    {"meshes/fertility_input.off", false},
                                    {"bun_zipper.ply", false}};

std::string shared_mesh_path(const char* file) {
  const std::string dir = shared_data_dir();
  const std::string path = dir + "/" + file;
  return dir.empty() || !std::filesystem::exists(path) ? "" : path;
}

TEST(RealMeshesShared, TruthIsSoundOnEveryMesh) {
  std::size_t found = 0;
  for (const SharedMesh& shared : kSharedMeshes) {
    SCOPED_TRACE(shared.file);
    const std::string path = shared_mesh_path(shared.file);
    if (path.empty()) continue;
    ++found;
    Mesh m = eval::read_mesh(path);
    eval::normalize_to_unit_diagonal(m);
    EXPECT_NEAR(eval::bounding_box_diagonal(m.vertices), 1, 1e-12);
    const MeshNormals normals = eval::mesh_normals(m);
    const MeshSamples s = eval::sample_mesh(m, normals, 20000, 16);
    // With the truth as input the input error is 0, and every true normal is a unit vector.
    const eval::AngleError e = eval::oriented_angle_error(s.shape.normals, s.shape.normals);
    EXPECT_EQ(e.rms_deg, 0);
    EXPECT_EQ(e.mean_deg, 0);
    for (const Vec3& n : s.shape.normals) ASSERT_NEAR(geometry::norm(n), 1, 1e-12);
    EXPECT_LE(eval::bounding_box_diagonal(s.shape.positions), 1 + 1e-12);
    // Oriented outward: at the extreme sample along each axis, either way, the normal points out.
    for (int axis = 0; axis < 3; ++axis) {
      for (const double sign : {1.0, -1.0}) {
        std::size_t extreme = 0;
        for (std::size_t i = 0; i < s.triangles.size(); ++i) {
          if (sign * s.shape.positions[i][axis] > sign * s.shape.positions[extreme][axis]) extreme = i;
        }
        EXPECT_GT(sign * s.shape.normals[extreme][axis], 0) << "axis " << axis << " sign " << sign;
      }
    }
  }
  if (found == 0)
    GTEST_SKIP() << "none of the shared meshes found under '" << shared_data_dir() << "' (set PNF_SHARED_DATA)";
}

// On the casting (a box-like CAD part, a fifth of its area on flat faces normal to y): a sample
// on a flat face, away from any face within 30 degrees of it that is not in its plane, has that
// face's normal; the faces at the top and bottom of the part point up and down.
TEST(RealMeshesShared, FlatFacesOfTheCastingHaveTheirFaceNormal) {
  const std::string path = shared_mesh_path("meshes/casting.off");
  if (path.empty())
    GTEST_SKIP() << "meshes/casting.off is absent under '" << shared_data_dir() << "' (set PNF_SHARED_DATA)";
  Mesh m = eval::read_mesh(path);
  eval::normalize_to_unit_diagonal(m);
  const MeshNormals normals = eval::mesh_normals(m);
  const MeshSamples s = eval::sample_mesh(m, normals, 20000, 17);
  // The faces around each vertex, from the mesh alone (no vertices share a position here).
  std::vector<std::vector<std::size_t>> around(m.vertices.size());
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    for (std::size_t v : m.triangles[t]) around[v].push_back(t);
  }
  double top = -1, bottom = 1;
  for (const Vec3& v : m.vertices) top = std::max(top, v[1]), bottom = std::min(bottom, v[1]);
  // Flat: every face around the triangle's corners that is within 30 degrees of it is within
  // 1e-4 degrees (the file's 6-digit coordinates tilt coplanar faces by about 1e-5).
  constexpr double kCoplanarDeg = 1e-4;
  std::size_t flat = 0, on_top = 0, on_bottom = 0;
  for (std::size_t i = 0; i < s.triangles.size(); ++i) {
    const std::size_t t = s.triangles[i];
    const Vec3 own = face_normal(m, t);
    bool is_flat = true;
    for (std::size_t v : m.triangles[t]) {
      for (std::size_t f : around[v]) {
        const double angle = angle_degrees(face_normal(m, f), own);
        if (angle > kCoplanarDeg && angle < eval::kCreaseAngleDeg) is_flat = false;
      }
    }
    if (!is_flat) continue;
    ++flat;
    ASSERT_LT(angle_degrees(s.shape.normals[i], own), kCoplanarDeg) << "sample " << i << " on triangle " << t;
    bool all_top = true, all_bottom = true;
    for (std::size_t v : m.triangles[t]) all_top &= m.vertices[v][1] == top, all_bottom &= m.vertices[v][1] == bottom;
    if (all_top) {
      ++on_top;
      EXPECT_LT(angle_degrees(s.shape.normals[i], {0, 1, 0}), kCoplanarDeg) << "sample " << i;
    }
    if (all_bottom) {
      ++on_bottom;
      EXPECT_LT(angle_degrees(s.shape.normals[i], {0, -1, 0}), kCoplanarDeg) << "sample " << i;
    }
  }
  // Over a third of the samples are on flat faces (7386 of 20000 at this seed); the top face is
  // small (52), the bottom large (2535).
  EXPECT_GT(flat, s.triangles.size() / 4);
  EXPECT_GT(on_top, 20u);
  EXPECT_GT(on_bottom, 1000u);
}

}  // namespace
}  // namespace pnf::test
