// pnf::choose_filter_params — filter parameters estimated from the data (the setting
// `pnf filter --auto` starts from).
//
// The paper's settings (FilterParams defaults: sigma_f 4, sigma_g 0.5 mean radii, 4 passes) suit
// lightly noisy models. choose_filter_params measures a cloud (pnf/estimate_data.hpp) and picks
// sigma_f, sigma_g and the passes by one documented rule (docs/auto.md, which also shows the
// evaluation behind it). The rule is written in area spacings; the parameters it returns are in
// mean surfel radii, like every other FilterParams: sigma_f in mean radii times the mean radius
// is sigma_f in area spacings times the area spacing.
#pragma once

#include <string>

#include "pnf/cloud_view.hpp"
#include "pnf/estimate_data.hpp"
#include "pnf/filter_params.hpp"

namespace pnf {

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

}  // namespace pnf
