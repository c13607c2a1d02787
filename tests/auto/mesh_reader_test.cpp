// The files pnf_eval_real reads (bench/real_meshes.hpp): meshes (bench/mesh_reader.cpp), and point
// sets whose normals are the truth (read_point_set). Malformed meshes give a std::runtime_error
// naming the file and the line.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>

#include "real_meshes.hpp"
#include "temp_dir.hpp"

namespace pnf::test {
namespace {

using eval::Mesh;

class RealMeshFiles : public ::testing::Test {
 protected:
  std::string write(const std::string& name, const std::string& text) {
    const std::string path = (folder_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
  void expect_error(const std::string& name, const std::string& text, const std::string& where,
                    const std::string& what) {
    const std::string path = write(name, text);
    try {
      eval::read_mesh(path);
      ADD_FAILURE() << name << ": no error";
    } catch (const std::runtime_error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(path + ":" + where + ":"), std::string::npos) << message;
      EXPECT_NE(message.find(what), std::string::npos) << message;
    }
  }

 private:
  TempDir folder_{"pnf_mesh_reader_test_"};
};

TEST_F(RealMeshFiles, ReadsOffAndPly) {
  const Mesh off =
      eval::read_mesh(write("quad.off", "OFF\n# a comment\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n"));
  ASSERT_EQ(off.vertices.size(), 4u);
  ASSERT_EQ(off.triangles.size(), 2u);  // the quad as a fan
  EXPECT_EQ(off.triangles[1], (std::array<std::size_t, 3>{0, 2, 3}));
  const Mesh same_line = eval::read_mesh(write("same_line.off", "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 255 0 0\n"));
  EXPECT_EQ(same_line.triangles.size(), 1u);
  const Mesh ply = eval::read_mesh(
      write("tri.ply",
            "ply\nformat ascii 1.0\ncomment x\nelement vertex 3\nproperty float x\nproperty float y\nproperty float "
            "z\nproperty float confidence\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
            "0 0 0 0.5\n1 0 0 0.5\n0 1 2 0.5\n3 0 1 2\n"));
  ASSERT_EQ(ply.vertices.size(), 3u);
  EXPECT_EQ(ply.vertices[2], (Vec3{0, 1, 2}));
  EXPECT_EQ(ply.triangles.size(), 1u);
}

TEST_F(RealMeshFiles, MalformedFilesNameTheLine) {
  expect_error("bad_magic.off", "OOF\n3 1 0\n", "1", "not an ASCII OFF file");
  expect_error("bad_coordinate.off", "OFF\n3 1 0\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n", "4", "bad y 'zero'");
  expect_error("bad_index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "6", "vertex index 3 out of range");
  expect_error("short.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "6", "ends before face 1 of 2");
  expect_error("two_corners.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "6", "at least 3");
  expect_error("binary.ply", "ply\nformat binary_little_endian 1.0\n", "2", "only ASCII PLY");
  expect_error("no_face.ply",
               "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
               "property float z\nend_header\n0 0 0\n",
               "7", "no 'element face'");
  expect_error("long_row.ply",
               "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
               "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0 7\n0 1 0\n3 0 1 2\n",
               "11", "4 values");
}

TEST_F(RealMeshFiles, UnknownExtensionIsNamed) {
  const std::string path = write("unknown.obj", "v 0 0 0\n");
  try {
    eval::read_mesh(path);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": unknown mesh format '.obj'"), std::string::npos) << e.what();
  }
}

// A point set's own normals are its truth: scaled like a mesh (centred, unit diagonal), the
// normals made unit and kept in the file's order.
TEST_F(RealMeshFiles, PointSetIsScaledAndItsNormalsMadeUnit) {
  const eval::Shape shape = eval::read_point_set(write("points.xyz", "0 0 0 0 0 2\n2 0 0 0 3 0\n2 2 1 1 0 0\n"));
  ASSERT_EQ(shape.positions.size(), 3u);
  // The box is 2 x 2 x 1 (diagonal 3), centred at (1, 1, 0.5).
  EXPECT_NEAR(shape.positions[0][0], -1.0 / 3, 1e-15);
  EXPECT_NEAR(shape.positions[2][2], 0.5 / 3, 1e-15);
  EXPECT_NEAR(eval::bounding_box_diagonal(shape.positions), 1.0, 1e-15);
  EXPECT_EQ(shape.normals[0], (Vec3{0, 0, 1}));
  EXPECT_EQ(shape.normals[1], (Vec3{0, 1, 0}));
  EXPECT_EQ(shape.normals[2], (Vec3{1, 0, 0}));
}

TEST_F(RealMeshFiles, PointSetWithoutNormalsIsRefused) {
  const std::string path = write("bare.xyz", "0 0 0\n1 0 0\n0 1 0\n");
  try {
    eval::read_point_set(path);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": the point set carries no normals"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pnf::test
