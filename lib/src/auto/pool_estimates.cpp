// pnf::pool_estimates: one DataEstimate from the estimates of the parts of a cloud (the ranks of
// a distributed run, each estimating its own slice).
#include <algorithm>
#include <cmath>
#include <string>

#include "pnf/auto_params.hpp"
#include "pnf/error.hpp"

namespace pnf {

DataEstimate pool_estimates(const std::vector<DataEstimate>& parts) {
  DataEstimate all;
  double samples = 0, estimated_points = 0, points_weighted_radius = 0, surface_area = 0, crease = 0, normal_crease = 0;
  double sharpness = 0, spacing = 0, noise = 0, normal_noise = 0, curved = 0, correlation = 0, coupling = 0, fit_radius = 0;
  bool normals = true;
  for (const DataEstimate& e : parts) {
    all.points += e.points;
    if (e.samples == 0) continue;  // too few points there to estimate: it does not count
    const double w = double(e.samples);
    samples += w;
    all.samples += e.samples;
    estimated_points += double(e.points);
    spacing += w * e.area_spacing;
    noise += w * e.position_noise;
    normals = normals && e.normal_noise_deg >= 0;
    normal_noise += w * e.normal_noise_deg;
    curved += w * e.curved_share;
    correlation += w * e.normal_error_correlation;
    coupling += w * e.normal_position_coupling;
    fit_radius += w * e.fit_radius;
    all.fit_neighbours = std::max(all.fit_neighbours, e.fit_neighbours);
    all.edge_samples += e.edge_samples;
    sharpness += double(e.edge_samples) * e.crease_sharpness;  // a median over the edge fits
    all.feature_samples += e.feature_samples;
    // The mean radius is a mean over points; the crease length a length, which adds up over the
    // parts (each part's crease_length is per the square root of its own area).
    points_weighted_radius += double(e.points) * e.mean_radius;
    const double area = double(e.points) * e.area_spacing * e.area_spacing;
    surface_area += area;
    crease += e.crease_length * std::sqrt(area);
    normal_crease += e.normal_crease_length * std::sqrt(area);
    all.radius_source = e.radius_source;
  }
  if (!(samples > 0)) {
    throw Error(ErrorCode::invalid_input, "pool_estimates: no part of the cloud has enough points to estimate (" +
                                              std::to_string(parts.size()) + " parts)");
  }
  all.mean_radius = points_weighted_radius / estimated_points;
  all.area_spacing = spacing / samples;
  all.position_noise = noise / samples;
  all.normal_noise_deg = normals ? normal_noise / samples : -1;
  all.curved_share = curved / samples;
  all.normal_error_correlation = correlation / samples;
  all.normal_position_coupling = coupling / samples;
  all.fit_radius = fit_radius / samples;
  all.feature_share = all.feature_samples > 0 ? double(all.edge_samples) / double(all.feature_samples) : 0;
  all.crease_sharpness = all.edge_samples > 0 ? sharpness / double(all.edge_samples) : 0;
  all.crease_length = surface_area > 0 ? crease / std::sqrt(surface_area) : 0;
  all.normal_crease_length = !normals ? -1 : surface_area > 0 ? normal_crease / std::sqrt(surface_area) : 0;
  return all;
}

}  // namespace pnf
