// Internal to --auto (pnf::estimate_data): how much sharp crease a cloud holds, measured so that
// the same surface sampled more densely measures the same (issue 14).
#pragma once

#include <cstddef>
#include <vector>

namespace pnf::detail {

// The fits of one neighbourhood size, reduced to what the crease measure needs.
struct CreaseFits {
  std::vector<double> residuals;  // each sample's fit residual, model units
  double fit_radius = 0;          // the cylinder radius of those fits (their median), model units
  double noise = 0;               // the position noise, model units (taken out of the residuals)
};

struct CreaseEvidence {
  std::size_t samples = 0;       // fits judged
  std::size_t edge_samples = 0;  // of them, fits whose residual passes edge_residual
  // The crease length those fits imply, in units of the square root of the surface's area
  // (DataEstimate::crease_length): a fit misses the surface when a crease passes through its
  // cylinder, so the edge fits cover a band about 2 fit radii wide along every crease, and the
  // crease length is L = (edge share) x area / (2 fit radius), with area = points x area_spacing^2.
  // The share of a band falls as 1 / sqrt(points) when the same surface is sampled more densely
  // (the fit radius is a fixed number of spacings); L / sqrt(area) does not.
  double length_per_size = 0;
  // How sharply the creases bend (DataEstimate::crease_sharpness): the median over the edge fits
  // of the residual the crease leaves, sqrt(residual^2 - noise^2), over the fit radius. A fit's
  // quadric absorbs part of a kink; what it leaves grows with the bend: 0 without edge fits.
  double sharpness = 0;
};

// The crease length (per the square root of the area) that a share of fits implies when the
// fits that see a crease cover a band of 2 fit radii along it: share x area / (2 fit_radius)
// / sqrt(area), area = points x area_spacing^2. 0 unless fit_radius and area_spacing are > 0.
double crease_length_per_size(double share, double fit_radius, std::size_t points, double area_spacing);

// `fits` at the scale where features are judged; `edge_residual` the residual above which a fit
// is at an edge (model units); `points` and `area_spacing` (model units) of the whole cloud.
// Preconditions: fit_radius and area_spacing > 0 (else length_per_size is 0).
CreaseEvidence crease_evidence(const CreaseFits& fits, double edge_residual, std::size_t points, double area_spacing);

}  // namespace pnf::detail
