// One sample's local fit (estimate_data.cpp's measurements): a PCA frame, a quadric over the
// cylinder around the sample, and the input normals against the quadric's.
#pragma once

#include <cstddef>
#include <vector>

#include "pnf/cloud_view.hpp"

namespace pnf::detail {

// The fitted cylinder has this fraction of the distance to the farthest neighbour as radius.
// Every point of the cylinder within sqrt(1 - 0.5^2) = 0.87 of that distance above or below the
// centre is then inside the neighbour ball, so the count in it measures the surface density
// even when the points are scattered along the normal.
constexpr double kCylinderFraction = 0.5;

// A quadric has 6 coefficients; ask for twice as many points in the cylinder for a stable
// residual (fewer: the sample is not fitted).
constexpr int kMinFitPoints = 12;

// One sample's fit at one scale.
struct SampleFit {
  bool ok = false;
  double area_spacing = 0;  // sqrt(pi rho^2 / count in the cylinder)
  double residual = 0;      // RMS distance to the quadric, corrected for the 6 fitted coefficients
  double angle_deg = -1;    // input normal vs quadric normal at the sample, as lines
  double radius = 0;        // rho
  double curvature = 0;     // the quadric's largest principal curvature magnitude, 1 / model units
  // Sums over the points within kCorrelationReachSpacings of the sample, of e_sample . e_point
  // and |e_sample| |e_point|, e being an input normal minus the quadric's normal at that point.
  double error_dot = 0;
  double error_magnitudes = 0;
  // e_input . e_positions, |e_input|^2 and |e_positions|^2 at the sample: e_input its input normal
  // minus the quadric's, e_positions a PCA normal of its kCouplingNeighbours nearest points minus
  // the quadric's (for DataEstimate::normal_position_coupling).
  double coupling_dot = 0;
  double coupling_input_squared = 0;
  double coupling_positions_squared = 0;
  // The mean over the sample and the points within kCorrelationReachSpacings of it of their input
  // normal minus the quadric's normal there, as an angle (degrees): small where the errors are
  // random, as large as the bend where a crease turns the input normals away from a quadric
  // that bends through it.
  double local_angle_deg = -1;
};

// Fits the neighbourhood `ids` (the sample itself included) of sample `self`: a PCA frame, then
// a quadric height field w(u, v) over the points of the cylinder of radius
// kCylinderFraction * (distance to the farthest neighbour) around the frame's axis through the
// sample. The cylinder is symmetric about the sample, so the quadric's slope there is not biased
// by curvature (the even terms are orthogonal to the odd ones). With normals, also compares the
// input normals with the quadric's: at the sample (angle_deg) and, for the correlation of the
// errors, at the points near it; and with a PCA normal of the nearest points (the coupling).
// `by_sheet` (normals_oriented): the frame and the quadric are fitted to the sample's own sheet
// only, the neighbours whose input normals do not face away from the sample's (the far wall of a
// thin part does); the spacing still counts every point of the cylinder.
SampleFit fit_sample(const std::vector<double>& centred, const CloudView& cloud, std::size_t self,
                     const std::size_t* ids, const double* squared_distances, int count, bool by_sheet);

struct SampleNeighbourhoods;
// Whether the cloud's normals are oriented, so that a neighbour whose normal faces away from a
// sample's lies on another sheet: at most a quarter of `nearest`'s samples have a nearest other
// point whose normal faces away from theirs. Normals of arbitrary sign face away from about half
// their nearest neighbours; oriented ones only where the nearest point is on another sheet, a
// wall thinner than the spacing, which the fits could not tell apart anyway. False without
// normals.
bool normals_oriented(const CloudView& cloud, const SampleNeighbourhoods& nearest);

}  // namespace pnf::detail
