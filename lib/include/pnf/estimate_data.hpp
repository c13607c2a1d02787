// pnf::estimate_data — what `pnf filter --auto` measures of a cloud: its spacing, the noise of
// its positions and normals, its creases and curvature (docs/auto.md).
//
// Two lengths appear here. The rule (pnf/choose_filter_params.hpp) is written in "area spacings"
// (the square root of the surface area per point, which estimate_data measures itself and which
// noise does not inflate); the mean radius is pnf's one spacing (pnf/mean_radius.hpp), the unit
// of every FilterParams.
#pragma once

#include <cstddef>

#include "pnf/cloud_view.hpp"
#include "pnf/filter_summary.hpp"  // RadiusSource

namespace pnf {

// What estimate_data measured. All lengths are Euclidean, in model units (never squared).
struct DataEstimate {
  std::size_t points = 0;   // N
  std::size_t samples = 0;  // points whose neighbourhoods were fitted (spread evenly along the Morton curve)
  // The mean surfel radius, pnf's one spacing (pnf::mean_radius): the mean of the cloud's radius
  // property when it has one (radius_source property), else estimate_mean_radius
  // (radius_source estimate). The same value `pnf info` and the filter's radius units use.
  double mean_radius = 0;
  RadiusSource radius_source = RadiusSource::not_used;
  // The density measure of the rule (its sigmas and noise ratios are in these units): the square
  // root of the surface area per point, from the count of neighbours inside a cylinder around
  // the fitted surface (so position noise does not inflate it). On a square grid of spacing h
  // it is h; on uniformly random samples about 1.2 times the estimated mean radius.
  double area_spacing = 0;
  // Standard deviation of the positions along the surface normal: the residual of local
  // quadric fits, the median over the samples. Where the cloud's normals are oriented, each fit
  // keeps to its sample's own sheet (the neighbours whose normals do not face away from the
  // sample's), so that the far wall of a thin part is not read as noise.
  double position_noise = 0;
  // RMS angle in degrees between the input normals and the normals of the fitted quadrics, as
  // lines (min(t, 180 - t)), from the median angle assuming a Rayleigh distribution; robust to
  // the minority of points near sharp edges. Negative when the cloud has no normals.
  double normal_noise_deg = -1;
  // RMS angle in degrees of the input normals' errors as their nearest neighbours' normals see
  // them: at each sample the normals of its 16 nearest points fitted as a linear function of the
  // position along the surface, the residuals' variance less what the position noise moves the
  // true normals by; the median, for Gaussian errors. Independent of the positions' fits, so it
  // is the errors' own size where they are independent from point to point (a scanner's, a
  // mesh's); errors shared by neighbours (PCA's) read low. With the chords' below, what
  // --auto's Stein risk estimate takes as the input's noise (docs/auto.md). -1 without normals,
  // or where position noise several spacings wide leaves under half the samples a fit.
  double normal_noise_neighbours_deg = -1;
  // RMS angle in degrees of the input normals' errors read from the chords to each sample's 3
  // nearest points: (p_j - p_i) . (n_i + n_j) / (2 |p_j - p_i|), in which the surface's curvature
  // cancels, so that detail finer than 16 points, which the estimate above reads as noise, does
  // not enter; position noise does (it reads high on noisy positions). Stein's estimate takes the
  // smaller of the two as the input's noise (docs/auto.md). -1 without normals.
  double normal_noise_chords_deg = -1;
  // The neighbourhood the fits used: number of nearest points, and the radius (model units)
  // of the fitted cylinder. The smallest of 64, 256, 1024, 4096 neighbours whose cylinder is
  // wide against the noise measured in it (kMaxNoiseToFitRadius in the source).
  int fit_neighbours = 0;
  double fit_radius = 0;
  // Share of the samples (0..1) whose quadric fit misses by more than 2 times the noise (or 0.15
  // spacings on clean data): neighbourhoods across a sharp edge or corner. Near 0 on smooth
  // shapes, and also where the noise hides the features. Judged two scales above fit_neighbours,
  // or fewer where 80% or more would miss there (a neighbourhood wider than a thin part).
  double feature_share = 0;
  // The length of sharp creases those edge fits imply, in units of the square root of the
  // surface's area, so that the same surface sampled 4 times denser measures the same (where the
  // feature share halves). Edge fits cover a band of about two fit radii along each crease:
  // length = feature_share x area / (2 x fit radius), the area being points x area_spacing^2.
  // Truly 1/sqrt 2 = 0.71 for two unit squares meeting at one crease (measured 0.45-1.3 for 60-90
  // degrees at 20k-400k points), 4.9 for a cube (measured 3.6); smooth shapes 0. Gentle or noisy
  // creases leave a narrower band and read short (135 degrees at 0.25 spacings of noise: 0-0.05).
  double crease_length = 0;
  // How sharply those creases bend: the median over the edge fits of what the crease leaves of
  // the fit's residual (the noise taken out in quadrature) over the fit radius. Grows with the
  // bend, whatever the density and noise: single creases of 60 / 90 / 120 / 135 / 150 degrees
  // (dihedral) measured 0.42-0.50 / 0.09-0.12 / 0.050-0.055 / 0.036-0.041 / 0.024 at 20k-100k
  // points and 0.1-0.5 spacings of noise, the cube (90) 0.10-0.13, a fold of 125 and 145 degrees
  // about 0.045. 0 without edge fits.
  double crease_sharpness = 0;
  std::size_t edge_samples = 0, feature_samples = 0;  // the fits at an edge, of all judged there
  // Crease seen in the input normals rather than the positions, in the same units as
  // crease_length: the share of those same fits where the input normals, averaged over some 20
  // points near the sample, turn from the quadric's normals by more than 5 times the median of
  // the same over all fits (and 3 degrees), as they do on either side of a crease that the
  // quadric bends through, converted to a length as above. Sees gentle creases whose kink the
  // quadrics absorb: a 150-degree crease at 0.1 spacings of noise measured 0.24-0.42 at
  // 20k-400k points (crease_length 0-0.02), planes and smooth shapes 0-0.02. -1 without normals.
  double normal_crease_length = -1;
  // Share of the smooth samples (0..1) whose fitted quadric curves by more than 0.015 per
  // spacing (a radius under about 67 spacings): near 0 on planes and polyhedra, near 1 on spheres.
  double curved_share = 0;
  // How alike the errors of nearby input normals are: the correlation (-1..1) of the input normals'
  // deviations from the fitted quadrics' normals, between points within 2.5 spacings, over the
  // clearly smooth fits (at an edge the quadric's own error would read as correlation). Near 0
  // for independent errors, about 0.02-0.3 for normals from small neighbourhoods (PCA over 16
  // points), 0.2-0.7 for normals already smoothed over several spacings (PCA over 64), whose
  // errors averaging cannot remove. 0 without normals.
  double normal_error_correlation = 0;
  // How much the input normals' errors follow the positions: the correlation (-1..1), over the
  // smooth samples, of each input normal's deviation from the fitted quadric's normal with the
  // deviation of a PCA normal over the sample's 16 nearest points. Near 1 for normals estimated
  // from these very positions by PCA over few neighbours, lower the more neighbours they
  // averaged; near 0 for normals whose errors are independent of the positions (from a scanner,
  // a mesh, or jittered), for which a neighbour's plane is off by its distance times its normal's
  // error. 0 without normals.
  double normal_position_coupling = 0;

  // position_noise / area_spacing (the rule's p), or 0 when area_spacing is 0.
  double position_noise_area_spacings() const { return area_spacing > 0 ? position_noise / area_spacing : 0.0; }
};

// Measures `cloud` (N positions, N >= 16, finite, float or double views of any stride; normals
// optional — with none, normal_noise_deg is -1; radii optional, finite and > 0). Deterministic: the
// same cloud gives the same estimate on every machine and thread count and in any row order (the
// samples are spread along the Morton curve, each one's neighbours taken nearest first with ties in
// curve order; only points tied with the k-th nearest, as on an exact grid, may be taken
// differently), and a float view the estimate of the same values as doubles. Cost: a kd-tree over
// the N points plus at most about 7 million neighbour look-ups and fits, whatever N (up to 4 scales
// for the noise, up to 3 for the features; about 2 million and 0.3 s on 2 cores for 100k clean
// points). Throws pnf::Error(invalid_input) for N < 16, a non-finite coordinate or a bad radius
// (naming the vertex), when no neighbourhood could be fitted (all points on a line or one spot, or
// too few: a random patch of 20 points has a neighbourhood a fit can use about half the time, of 25
// in 195 of 200 tries), or
// when the mean radius cannot be estimated. Thread safety: may be called concurrently.
DataEstimate estimate_data(const CloudView& cloud);

}  // namespace pnf
