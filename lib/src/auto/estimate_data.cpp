// pnf::estimate_data: the measurements behind `pnf filter --auto` (the rule that turns them into
// parameters is choose_filter_params.cpp). Local quadric fits at a few neighbourhood sizes on a
// sample of the points give the area spacing, the position noise, the share of samples at an
// edge, the curved share and the input normals' noise.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "cloud_checks.hpp"
#include "crease_evidence.hpp"
#include "mean_radius_internal.hpp"
#include "neighbour_normal_noise.hpp"
#include "pnf/choose_filter_params.hpp"
#include "pnf/error.hpp"
#include "sample_fit.hpp"
#include "sample_neighbourhoods.hpp"
#include "spatial/spatial_index.hpp"
#include "spatial/spatial_order.hpp"
#include "surface_judge.hpp"

namespace pnf {
namespace {

// Neighbourhood sizes tried, smallest first. Small ones see the fewest sharp edges and the least
// curvature beyond second order; large ones are needed where the noise is thick against the
// spacing (fandisk at 1.2% of its diagonal: about 5 spacings). Each is 4 times the last, so the
// fitted radius doubles. The cylinder holds about a quarter of them: 16 points at the smallest.
constexpr int kScales[] = {64, 256, 1024, 4096};
constexpr int kScaleStep = 4;  // each scale's neighbours over the last's
// A scale is trusted when the noise it measures is below this fraction of its cylinder radius:
// then the neighbour ball holds the noisy layer whole (more than 5 sigma of margin) and PCA finds
// the surface's plane. Measured against the noise added to the real meshes (100k points;
// docs/auto.md, "Plain averaging held to the judge's fits; the noise read where the fit holds
// it"): at the smallest scale at most 0.67 of the radius the reading was within 7% of the truth
// (20-28% low from 0.74), while each wider scale read the shape's detail as noise too: 20 of the
// meshes' 36 rows at 0.6% of the diagonal read 1.5 to over 6 times their noise. A bound of 0.6
// read them right, but sent sparse noisy detail to Stein's estimate, whose noise reading the
// detail inflates (11 rows at 6k-20k points came back worse than their input): not changed until
// that reading is.
constexpr double kMaxNoiseToFitRadius = 0.3;
// Features and normals are judged on the fits this many scales above the noise scale.
constexpr int kUpperScaleSteps = 2;
// A sample there is "at a feature" when its fit residual passes this many times the noise: the
// spread of one sample's residual about the noise is about 1 / sqrt(2 (m - 6)), under 5% with
// the ~256 points of the cylinder two scales up, so 2 is out of the noise's reach.
constexpr double kEdgeResidualPerNoise = 2.0;
// ... or this fraction of the spacing, on clean data: the third-order terms of smooth surfaces
// stay below it (a torus of minor radius 14 spacings: 0.1), a 90-degree edge in the cylinder
// leaves about a tenth of its radius (about 1 spacing).
constexpr double kResidualFloorPerSpacing = 0.15;
// More than this share of fits at an edge means the scale is too wide for the shape: shapes with
// edges measured 15-50% (the cube 46%); a torus of tube radius 9 spacings 97% at 1024 neighbours.
constexpr double kImplausibleFeatureShare = 0.8;
// Curvature is read from fits whose residual is within this many times the noise: the residual's
// spread about the noise is under 5% there, and fits that graze an edge (whose curvature is the
// edge's, not the surface's) stay out.
constexpr double kSmoothResidualPerNoise = 1.25;
// A fit is "curved" when its largest principal curvature passes this many per spacing (a radius
// of curvature under 67 spacings). Noise leaves at most about 0.01 per spacing at half a spacing
// of noise two scales up; planes and polyhedra measured 0-8% curved, the cylinder 71%, fandisk 22-84%.
constexpr double kCurvedPerSpacing = 0.015;
// DataEstimate::normal_crease_length: a fit sees a crease in the input normals where their mean
// error about it (over the sample and its points within kCorrelationReachSpacings) passes this
// many times the median of the same over all fits, and this many degrees. Averaging some 20
// normals takes random errors down; the turn of the normals on either side of a crease that the
// quadric bends through stays. PCA's errors have long tails, more of them read the denser the
// cloud: planes with PCA-16 normals at 0.5 spacings of noise read up to 0.49 at 3 times the
// median (400k points), 0.10 at 4, 0.00-0.02 at 5, where a 150-degree crease at 0.1 spacings of
// noise still reads 0.24-0.42 (20k-400k points).
constexpr double kNormalCreasePerTypical = 5.0;
constexpr double kNormalCreaseFloorDeg = 3.0;
// The median of a Rayleigh distribution is sigma sqrt(2 ln 2) and its RMS sigma sqrt(2).
const double kRayleighRmsPerMedian = std::sqrt(2.0) / std::sqrt(2.0 * std::log(2.0));

// What estimate_data needs of a cloud: enough points for the smallest fit; normals optional and
// not checked (a bad input normal only leaves its sample out of the angular noise).
detail::CloudRequirements estimate_requirements() {
  detail::CloudRequirements requirements;
  requirements.caller = "estimate_data";
  requirements.min_points = 16;
  requirements.checks_normals = false;
  return requirements;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  auto middle = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

}  // namespace

DataEstimate detail::estimate_data(const CloudView& cloud, SurfaceJudge* judge,
                                   const std::function<bool(double fraction)>& poll) {
  detail::check_cloud(cloud, estimate_requirements());
  const std::size_t count = cloud.size();
  // Coordinates relative to the middle of the points: a far-away scan loses no digits in the fits.
  // The points stay in input order (the normals come in it), so the tree keeps its own copy in
  // leaf order. The samples are spread along the Morton curve and each one's neighbours taken in
  // canonical order (sort_neighbours), so that the estimate does not depend on the input's row
  // order.
  const std::vector<std::uint32_t> curve = detail::morton_order(cloud.positions);
  const Vec3 centre = detail::sample_median(cloud.positions, curve);  // the filter's origin
  const detail::SpatialIndex index(detail::centred_rows(cloud.positions, centre),
                                   detail::SpatialIndex::Layout::any_order);
  const std::vector<double>& centred = index.positions();
  const std::vector<std::uint32_t> rank = detail::ranks_of(curve);
  // Each scale's samples are searched once (sample_neighbourhoods) and fitted once, in parallel:
  // the upper fits may fall on the noise scale, the judge on either. The calling thread (OpenMP's
  // master) asks `poll` during the searches; the k-th scale searched reports within
  // [1 - 2^-k, 1 - 2^-(k+1)) of the work (how many scales run depends on what the first ones find).
  // The searches are kept until the estimate returns: 16 bytes a look-up, up to 16 MB a scale.
  using Scale = std::pair<std::size_t, int>;  // samples, and neighbours with the sample
  std::map<Scale, detail::SampleNeighbourhoods> searched;
  std::map<Scale, std::vector<SampleFit>> fitted;
  auto neighbourhoods_of = [&](std::size_t samples, int neighbours) -> const detail::SampleNeighbourhoods& {
    const Scale key(std::min(samples, count), neighbours);
    auto found = searched.find(key);
    if (found != searched.end()) return found->second;
    const int k = int(searched.size());
    const double from = 1 - std::ldexp(1.0, -k), share = std::ldexp(1.0, -k - 1);
    auto report = [&](double fraction) { return !poll || poll(from + share * fraction); };
    return searched[key] =
               detail::sample_neighbourhoods(index, curve, rank, key.first, neighbours, report, "estimate_data");
  };
  // Whether the fits keep to each sample's own sheet (sample_fit.hpp), read from the smallest
  // scale's neighbourhoods, which the first fits search anyway.
  const int smallest = int(std::min<std::size_t>(std::size_t(kScales[0]), count - 1)) + 1;  // the sample too
  const bool by_sheet =
      detail::normals_oriented(cloud, neighbourhoods_of(detail::samples_at_scale(count, smallest), smallest));
  auto fit_scale = [&](int scale) -> const std::vector<SampleFit>& {
    const int neighbours = int(std::min<std::size_t>(std::size_t(scale), count - 1)) + 1;  // the sample too
    const Scale key(detail::samples_at_scale(count, neighbours), neighbours);
    auto found = fitted.find(key);
    if (found != fitted.end()) return found->second;
    const detail::SampleNeighbourhoods& n = neighbourhoods_of(key.first, neighbours);
    std::vector<SampleFit> fits(n.samples());
#pragma omp parallel for schedule(dynamic, 16)
    for (long long s = 0; s < static_cast<long long>(n.samples()); ++s) {
      fits[std::size_t(s)] = fit_sample(centred, cloud, n.selves[std::size_t(s)], n.ids_of(std::size_t(s)),
                                        n.squared_distances_of(std::size_t(s)), neighbours, by_sheet);
    }
    fits.erase(std::remove_if(fits.begin(), fits.end(), [](const SampleFit& f) { return !f.ok; }), fits.end());
    return fitted[key] = std::move(fits);
  };
  auto medians = [](const std::vector<SampleFit>& fits, double SampleFit::*field) {
    std::vector<double> values;
    for (const SampleFit& f : fits) values.push_back(f.*field);
    return median(values);
  };

  // Noise and spacing at the smallest trusted scale.
  DataEstimate estimate;
  estimate.points = count;
  // The one mean radius, sampled as the filter samples it (along the Morton order), so that the
  // value is the filter's and `pnf info`'s bit for bit.
  const MeanRadius radius =
      detail::resolve_mean_radius(0, cloud.radii, count, [&] { return detail::estimate_mean_radius(index, &curve); });
  estimate.mean_radius = radius.value;
  estimate.radius_source = radius.source;
  const int scales = int(std::size(kScales));
  int chosen = -1;
  for (int i = 0; i < scales; ++i) {
    const std::vector<SampleFit>& fits = fit_scale(kScales[i]);
    if (fits.empty()) continue;
    chosen = i;
    estimate.samples = fits.size();
    estimate.area_spacing = medians(fits, &SampleFit::area_spacing);
    estimate.position_noise = medians(fits, &SampleFit::residual);
    estimate.fit_neighbours = int(std::min<std::size_t>(std::size_t(kScales[i]), count - 1));
    estimate.fit_radius = medians(fits, &SampleFit::radius);
    if (estimate.position_noise <= kMaxNoiseToFitRadius * estimate.fit_radius) break;
    if (std::size_t(kScales[i]) >= count - 1) break;  // no larger neighbourhood exists
  }
  if (chosen < 0) {
    throw Error(
        ErrorCode::invalid_input,
        "estimate_data: no neighbourhood of the " + std::to_string(count) +
            " points could be fitted with a surface (a fit needs " + std::to_string(detail::kMinFitPoints) +
            " points within " + std::to_string(int(100 * detail::kCylinderFraction)) + "%" +
            " of its neighbourhood's radius from the sample's normal axis): are the points on a line or one spot, "
            "or too few (a random patch of 20 points has such a neighbourhood about half the time, of 25 nearly "
            "always)?");
  }
  // Features and normals are judged on the fits two scales up (16 times the points, twice the
  // radius). There a sharp edge inside the cylinder leaves a residual well above the noise, and
  // the quadric's slope moves with the noise a quarter as much as at the noise scale. The fits
  // hold many more points than a PCA normal of up to ~100 neighbours, whose errors are then
  // nearly independent of theirs (a correction in quadrature would need that independence; two
  // scales up it is not needed).
  const double edge_residual =
      kEdgeResidualPerNoise * std::max(estimate.position_noise, kResidualFloorPerSpacing * estimate.area_spacing);
  auto share_at_edges = [&](const std::vector<SampleFit>& fits) {
    std::size_t edges = 0;
    for (const SampleFit& f : fits) edges += f.residual > edge_residual;
    return double(edges) / double(std::max<std::size_t>(1, fits.size()));
  };
  // Nearly every fit missing the surface is a neighbourhood too wide for the shape (a tube a few
  // cylinder radii thick, seen whole from one side), not a cloud of edges: one scale down then.
  std::vector<SampleFit> fits;
  for (int upper_scale = std::min(chosen + kUpperScaleSteps, scales - 1); upper_scale >= chosen; --upper_scale) {
    fits = fit_scale(kScales[upper_scale]);
    if (fits.empty()) continue;
    estimate.feature_share = share_at_edges(fits);
    if (estimate.feature_share < kImplausibleFeatureShare) break;
  }
  // How much crease those edge fits mean on the surface, whatever the sampling density (issue 14).
  {
    detail::CreaseFits crease_fits;
    for (const SampleFit& f : fits) crease_fits.residuals.push_back(f.residual);
    crease_fits.fit_radius = medians(fits, &SampleFit::radius);
    crease_fits.noise = estimate.position_noise;
    const detail::CreaseEvidence evidence =
        detail::crease_evidence(crease_fits, edge_residual, count, estimate.area_spacing);
    estimate.crease_length = evidence.length_per_size;
    estimate.crease_sharpness = evidence.sharpness;
    estimate.edge_samples = evidence.edge_samples;
    estimate.feature_samples = evidence.samples;
  }
  // Curvature is judged only on fits that are clearly smooth (residual within the noise's own
  // spread): a fit grazing an edge reports a large curvature.
  const double smooth_residual =
      kSmoothResidualPerNoise * std::max(estimate.position_noise, kResidualFloorPerSpacing * estimate.area_spacing);
  std::size_t smooth = 0, curved = 0;
  for (const SampleFit& f : fits) {
    if (f.residual > smooth_residual) continue;
    ++smooth;
    curved += f.curvature * estimate.area_spacing > kCurvedPerSpacing;
  }
  estimate.curved_share = double(curved) / double(std::max<std::size_t>(1, smooth));
  if (judge) {
    const detail::JudgeGeometry g = detail::judge_geometry(estimate);
    const int neighbours = int(std::min<std::size_t>(std::size_t(g.neighbours), count));
    *judge = detail::SurfaceJudge(centred, neighbourhoods_of(g.samples, neighbours), g.width);
  }
  if (cloud.has_normals()) {
    // The smallest scale's neighbourhoods (searched first, always), nearest first.
    const detail::SampleNeighbourhoods& nearest =
        neighbourhoods_of(detail::samples_at_scale(count, smallest), smallest);
    estimate.normal_noise_neighbours_deg =
        detail::neighbour_normal_noise_deg(centred, cloud, nearest, estimate.position_noise);
    estimate.normal_noise_chords_deg = detail::chord_normal_noise_deg(centred, cloud, nearest);
    estimate.normal_noise_deg = medians(fits, &SampleFit::angle_deg) * kRayleighRmsPerMedian;
    const double turned_deg =
        std::max(kNormalCreasePerTypical * medians(fits, &SampleFit::local_angle_deg), kNormalCreaseFloorDeg);
    std::size_t turned = 0;
    for (const SampleFit& f : fits) turned += f.local_angle_deg > turned_deg;
    estimate.normal_crease_length = detail::crease_length_per_size(
        double(turned) / double(fits.size()), medians(fits, &SampleFit::radius), count, estimate.area_spacing);
    // The reference is the quadric two scales up (one where the step-down above was taken),
    // fitted to 16 times the points of a PCA normal of 64 neighbours: at the noise scale the fit
    // shares the input normals' neighbours and with them most of their errors, and the
    // correlation measured there was near 0 for PCA-16 and PCA-64 alike.
    // Over the clearly smooth fits only, as the coupling below: at an edge the quadric's own error
    // is in every nearby point's error and reads as correlation.
    double dot = 0, magnitudes = 0;
    for (const SampleFit& f : fits) {
      if (f.residual > smooth_residual) continue;
      dot += f.error_dot;
      magnitudes += f.error_magnitudes;
    }
    estimate.normal_error_correlation = magnitudes > 0 ? dot / magnitudes : 0;
    double coupling = 0, input_squared = 0, positions_squared = 0;
    for (const SampleFit& f : fits) {
      if (f.residual > smooth_residual) continue;
      coupling += f.coupling_dot;
      input_squared += f.coupling_input_squared;
      positions_squared += f.coupling_positions_squared;
    }
    const double scale = std::sqrt(input_squared * positions_squared);
    estimate.normal_position_coupling = scale > 0 ? coupling / scale : 0;
  }
  return estimate;
}

DataEstimate estimate_data(const CloudView& cloud) { return detail::estimate_data(cloud, nullptr); }

detail::JudgeGeometry detail::judge_geometry(const DataEstimate& estimate) {
  JudgeGeometry g;
  // One scale above the noise scale (four times its points, up to the largest scale): at the
  // noise scale itself the judge shares the errors of normals fitted to as many points (PCA over
  // 64: the plane at 0.25 spacings of noise kept its input, 1.20 deg, where one scale up passed
  // 0.22), and one scale up the weights still keep the fit on one sheet. As many samples as
  // estimate_data fits at one scale; a width that holds a sheet's own points: the clean floor's
  // residual (the quadric's third-order terms) and the one an edge fit is told by, in quadrature.
  g.neighbours = std::min(kScaleStep * estimate.fit_neighbours, kScales[std::size(kScales) - 1]) + 1;  // the sample too
  g.samples = samples_at_scale(estimate.points, g.neighbours);
  const double floor = kResidualFloorPerSpacing * estimate.area_spacing;
  g.width = std::hypot(floor, kEdgeResidualPerNoise * estimate.position_noise);
  g.quarter_allowed = kEdgeResidualPerNoise * estimate.position_noise <= floor;
  return g;
}

}  // namespace pnf
