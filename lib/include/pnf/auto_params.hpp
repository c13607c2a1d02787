// pnf::choose_filter_params — filter parameters estimated from the data (`pnf filter --auto`).
//
// The paper's settings (FilterParams defaults: sigma_f 4, sigma_g 0.5 mean radii, 4 passes) suit
// lightly noisy models. This header measures a cloud — its sample density, the noise of its
// positions along the normal, the angular noise of its normals — and picks sigma_f, sigma_g and
// the passes by one documented rule (docs/auto.md, which also shows the evaluation behind it).
//
// Two lengths appear here. The rule is written in "area spacings" (the square root of the
// surface area per point, which --auto measures itself and which noise does not inflate); the
// parameters it returns are in mean surfel radii, pnf's one spacing (pnf/mean_radius.hpp), like
// every other FilterParams. The lengths in model units are the rule's: sigma_f in mean radii
// times the mean radius is sigma_f in area spacings times the area spacing.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "pnf/cloud_view.hpp"
#include "pnf/filter_params.hpp"
#include "pnf/normal_filter.hpp"  // RadiusSource
#include "pnf/point_cloud.hpp"

namespace pnf {

// What estimate_data measured. All lengths are Euclidean, in model units (never squared).
struct DataEstimate {
  std::size_t points = 0;   // N
  std::size_t samples = 0;  // points whose neighbourhoods were fitted (spread evenly through the cloud)
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
  // quadric fits, the median over the samples.
  double position_noise = 0;
  // RMS angle in degrees between the input normals and the normals of the fitted quadrics, as
  // lines (min(t, 180 - t)), from the median angle assuming a Rayleigh distribution; robust to
  // the minority of points near sharp edges. Negative when the cloud has no normals.
  double normal_noise_deg = -1;
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
// optional — with none, normal_noise_deg is -1; radii optional, finite and > 0). Deterministic:
// the same cloud gives the same estimate on every machine and thread count, and a float view
// the estimate of the same values as doubles. Cost: a kd-tree over the N points plus at most about 7 million
// neighbour look-ups and fits, whatever N (up to 4 scales for the noise, up to 3 for the
// features; about 2 million and 0.3 s on 2 cores for 100k clean points).
// Throws pnf::Error(invalid_input) for N < 16, a non-finite coordinate or a bad radius (naming
// the vertex), when no neighbourhood could be fitted (all points on a line or one spot), or
// when the mean radius cannot be estimated.
// Thread safety: may be called concurrently.
DataEstimate estimate_data(const CloudView& cloud);

// One estimate of a whole cloud from the estimates of its parts (a distributed run's ranks, each
// estimating its own slice): the points, samples and edge fits add up; the crease lengths add
// up as lengths (each part's is per the square root of its own area); the mean radius is
// averaged over the points, the crease sharpness over the edge fits; every other field is
// averaged, weighted by the samples. Parts with
// no samples count only their points. Throws pnf::Error(invalid_input) when no part has samples.
// Thread safety: pure function.
DataEstimate pool_estimates(const std::vector<DataEstimate>& parts);

// The outcome of the rule: parameters ready for NormalFilter::run, what they came from, and the
// rule as one line of text for reports.
struct AutoChoice {
  FilterParams params;  // units radius, mean_radius = estimate.mean_radius (model units)
  DataEstimate estimate;
  std::string rule;  // e.g. "noise 0.48 spacings, normals 9.1 deg -> sigma_f 4, sigma_g 1.2, ..."
  // Where improve_normals_auto judged the passes (below): what the judge measured and kept.
  std::string judged;
};

// The rule (docs/auto.md), with p = position_noise / area_spacing, sigmas in area spacings
// (then converted to mean radii: times area_spacing / mean_radius), "edges" meaning
// crease_length >= 0.15 (not a share of the samples, which falls as the density grows), or on a
// flat shape normal_crease_length >= 0.15 (faint creases: then as flat faces between gentle
// creases), "curved" curved_share >= 15%, and g(p) = min(0.2 + 1.5 p, sqrt(0.2^2 + (2 p)^2)):
//   p > 3 (noise hides the edges): sigma_f 8.5, feature term off (sigma_g 1e6), 14 passes;
//   input normals whose errors are independent of the positions (normal_position_coupling and
//   normal_error_correlation both under 0.35) on noisy positions (p >= 0.05), on curved shapes
//   or flat faces between sharp creases (crease_sharpness from 0.06): one pass (two from
//   normal_noise_deg 9 up), sigma_f 4 and sigma_g 2 with edges, sigma_f 8 and the feature term
//   off on smooth curved shapes (flat faces with gentle creases or none: the lines below);
//   edges, flat faces: sigma_f 6.5, sigma_g g(p), 8 passes (4 between gentle creases,
//   crease_sharpness under 0.06, when normal_noise_deg is under 9);
//   edges, curved faces: sigma_f min(1.6 + 6 sqrt(p), 12), sigma_g g(p); 8 passes when
//     p < 0.05, else with crease_length from 3.5 (small features) floor(1.1 / p) within [2, 8],
//     below it 4;
//   smooth, flat: sigma_f 8, sigma_g 0.2 + 3 p (pnf's rule, not the paper's: a crease too faint
//     to measure is kept rather than blurred), 8 passes;
//   smooth, curved: sigma_f 8, feature term off; 0 passes (the input is kept) when p < 0.05 and
//     normal_noise_deg < 0.6; when p < 0.05 and normal_error_correlation >= 0.2 instead sigma_f
//     3.3, sigma_g g(p), 1 pass (the clean positions re-derive already-smoothed normals);
//     else 1 pass when normal_noise_deg < 3, else 2 (also without normals);
//   always: stop_change_deg 0.01 (passes end once the normals move less on average).
// The constants and their reasons are in choose_filter_params.cpp. Throws
// pnf::Error(invalid_argument) when area_spacing or mean_radius is not > 0 and finite.
// Thread safety: pure function.
AutoChoice choose_filter_params(const DataEstimate& estimate);

// estimate_data then the rule above.
AutoChoice choose_filter_params(const CloudView& cloud);

// Whether the choice's estimate shows input normals whose errors are independent of the
// positions and of each other (normal_position_coupling and normal_error_correlation both under
// 0.35, normal_noise_deg from 0.6, p up to 3; on clean positions, p < 0.05, the correlation
// under 0.1), in 2000 points or more: such normals (a scanner's, a mesh's) defeat the rule's
// lines for PCA normals, so improve_normals_auto judges the rule's independent-errors setting
// beside the rule's own (docs/auto.md).
// Thread safety: pure function.
bool independent_normal_errors(const AutoChoice& choice);

// What improve_normals_auto did.
struct AutoRun {
  // The choice, with params.iterations the passes kept (0: the input normals were kept).
  AutoChoice choice;
  FilterSummary summary;  // the filter's run (passes_run: the passes tried)
  int passes_kept = 0;
  // The judge's RMS angle (degrees) to the surface fitted to the positions, of the input normals
  // and after each pass; empty when no pass ran or no fit was smooth enough to judge.
  std::vector<double> judged_rms_deg;
};

// `pnf filter --auto` in one call: choose_filter_params(cloud), then the chosen
// passes, each judged against the normals of local quadric fits to the positions (a jet fit of
// order 2, without the input normals) at the samples where the fit is smooth; the pass whose
// normals agree best with them is kept, and the input normals (normalised) when none beats them,
// so on the judged parts of the surface --auto never returns normals further from the positions'
// surface than its input (docs/auto.md). Writes N unit normals into normals_out (N rows; it may
// be the cloud's own normals view). A stop_change_deg >= 0 replaces the rule's stop rule (0: off).
// Throws as choose_filter_params and NormalFilter::run do.
AutoRun improve_normals_auto(const CloudView& cloud, MutableVec3ArrayView normals_out, NormalFilter& filter,
                             const ProgressCallback& progress = {}, double stop_change_deg = -1);

}  // namespace pnf
