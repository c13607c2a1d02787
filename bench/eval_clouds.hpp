// Clouds with known normals for pnf_eval_auto: the synthetic shapes (the tuning shapes and the
// held-out family of issue 14), position noise, input normals (PCA or jittered truth) and the
// score, the RMS angle to the truth as lines. Deterministic: the same seed, the same cloud.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "pnf/point_cloud.hpp"

namespace pnf::eval {

Vec3 add(const Vec3& a, const Vec3& b);
Vec3 scale(const Vec3& a, double s);
double dot(const Vec3& a, const Vec3& b);
Vec3 unit(const Vec3& a);

// A filter setting as the evaluations print it: "sigma_f/sigma_g/passes", sigma_g "off" from 1e5.
std::string setting_text(double sigma_f, double sigma_g, int passes);

// What a shell command printed on stdout, trailing newlines removed ("" when it cannot run): the
// benches' commit stamp.
std::string command_output(const char* command);

// RMS of the angle between lines (min(t, 180 - t)), in degrees.
double rms_line_angle(const std::vector<Vec3>& normals, const std::vector<Vec3>& truth);

// A surface with known normals: N points uniformly over its area.
struct Shape {
  std::string name;
  std::vector<Vec3> positions, normals;
  double area = 0;
};

// The tuning shapes: plane, sphere, cube, wedges, cylinder, torus, fold (the source says what
// each is); throws std::runtime_error for another name.
Shape make_shape(const std::string& name, std::size_t points, unsigned seed);
// The held-out family: two unit squares meeting at a dihedral angle of `degrees`; a capped
// cylinder of radius 0.25 and height 2; a 1 x 1 x 0.6 box with rounded vertical edges.
Shape make_crease(double degrees, std::size_t points, unsigned seed);
Shape make_long_cylinder(std::size_t points, unsigned seed);
Shape make_rounded_box(std::size_t points, unsigned seed);

// Gaussian noise of `sigma` (model units) per axis.
void add_noise(std::vector<Vec3>& positions, double sigma, unsigned seed);
// PCA normals over k points (the point itself included, as EstimateParams::k counts), turned to
// the true side (a sign only).
std::vector<Vec3> pca_normals(const std::vector<Vec3>& positions, const std::vector<Vec3>& truth, int k);
// The true normals, each tilted by a Gaussian angle of `rms_degrees` RMS.
std::vector<Vec3> jittered_normals(const std::vector<Vec3>& truth, double rms_degrees, unsigned seed);

}  // namespace pnf::eval
