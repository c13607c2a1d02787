// pnf::FilterParams — the parameters of the normal filter (docs/method.md, "Parameters and units").
#pragma once

namespace pnf {

// How sigma_f and sigma_g are measured.
enum class Units {
  radius,    // multiples of the cloud's mean surfel radius (the paper's convention)
  absolute,  // model units
};

// Returns "radius" or "absolute".
const char* to_string(Units units);

struct FilterParams {
  // Width of the spatial Gaussian f; neighbours reach 2 * sigma_f. > 0, finite. Default 4
  // (the paper's setting for its face model).
  double sigma_f = 4.0;
  // Width of the influence Gaussian g on the distance to a neighbour's tangent plane: the
  // feature-preserving term. > 0, finite. Default 0.5.
  double sigma_g = 0.5;
  // Number of passes; each pass uses the previous pass's normals (Jacobi). >= 0. Default 4.
  // With stop_change_deg > 0 this is the most passes that run.
  int iterations = 4;
  // Stop rule: when > 0, passes end early once the mean angle between a pass's normals and the
  // previous pass's falls below this many degrees. 0 (default): always run `iterations` passes.
  // >= 0, finite. Costs one read-back of the normals per pass.
  double stop_change_deg = 0.0;
  // Units of sigma_f and sigma_g. Default Units::radius.
  Units units = Units::radius;
  // The mean surfel radius in model units, for Units::radius. 0 (default) means: the mean of the
  // cloud's radii when it has them, else the estimate of estimate_mean_radius(). >= 0, finite.
  double mean_radius = 0.0;

  // Throws pnf::Error(invalid_argument) naming the first bad field and its value.
  void validate() const;
};

}  // namespace pnf
