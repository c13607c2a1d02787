#include "pnf/auto_params.hpp"

// Only the two FLANN headers needed: the whole of flann/flann.hpp pulls in every index type.
#include <flann/algorithms/dist.h>
#include <flann/algorithms/kdtree_single_index.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "bounding_box.hpp"
#include "pnf/error.hpp"

namespace pnf {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Neighbourhood sizes tried, smallest first. Small ones see the fewest sharp edges and the least
// curvature beyond second order; large ones are needed where the noise is thick against the
// spacing (fandisk at 1.2% of its diagonal: about 5 spacings). Each is 4 times the last, so the
// fitted radius doubles. The cylinder holds about a quarter of them: 16 points at the smallest.
constexpr int kScales[] = {64, 256, 1024, 4096};
// At most this many neighbour look-ups per scale (samples x neighbours): bounds the cost on
// any N while leaving hundreds of samples for the medians even at the largest scale.
constexpr std::size_t kMaxLookupsPerScale = 1000000;
// Never more samples than this at any scale: a median of 4000 is good to about 2%.
constexpr std::size_t kMaxSamples = 4000;
// The fitted cylinder has this fraction of the distance to the farthest neighbour as radius.
// Every point of the cylinder within sqrt(1 - 0.5^2) = 0.87 of that distance above or below the
// centre is then inside the neighbour ball, so the count in it measures the surface density
// even when the points are scattered along the normal.
constexpr double kCylinderFraction = 0.5;
// A scale is trusted when the noise it measures is below this fraction of its cylinder radius:
// then the neighbour ball holds the noisy layer whole (more than 5 sigma of margin) and PCA finds
// the surface's plane. Where noise fills the ball, the fit sees a blob and reports about 0.6 of
// the radius, so the test separates the two.
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
// The correlation of the input normals' errors is taken between each sample and the points within
// this many spacings of it: PCA normals from 16 neighbours (a radius of about 2.3 spacings) share
// little there, from 64 (4.5 spacings) most of their neighbours.
constexpr double kCorrelationReachSpacings = 2.5;
// A quadric has 6 coefficients; ask for twice as many points for a stable residual.
constexpr int kMinFitPoints = 12;
// The median of a Rayleigh distribution is sigma sqrt(2 ln 2) and its RMS sigma sqrt(2).
const double kRayleighRmsPerMedian = std::sqrt(2.0) / std::sqrt(2.0 * std::log(2.0));

// The rule's constants (docs/auto.md shows the evaluation they come from). Sigmas in spacings,
// p = position noise / spacing. Four kinds of data, by the estimate's feature share (edges or not)
// and curved share (a plane or polyhedron, or curved surfaces):
//
// Fewer samples than this share at a feature (DataEstimate::feature_share) is a smooth shape:
// nothing to keep sharp, so the feature term is off. Smooth shapes measured 0-4%, shapes with
// edges 15-50%.
constexpr double kSmoothShare = 0.08;
// A curved share (DataEstimate::curved_share) from this up is a curved shape: flat shapes
// measured 0-8%, the cylinder 71%, fandisk 22-84%, spheres and tori 100%.
constexpr double kCurvedShare = 0.15;
// sigma_g must pass the spread of the distances to the neighbours' planes on one surface (about
// sqrt 2 times the noise, as both ends are noisy) and no more, so that planes across a sharp
// edge are still refused: the grid optima (0.2 spacings clean, 0.6-1.1 at 0.25-0.5, 3 at 2)
// lie on this line.
constexpr double kSigmaG0 = 0.2;
constexpr double kSigmaGPerNoise = 1.5;
// Flat faces between edges: a wide sigma_f and 8 passes at every noise level (each pass sharpens
// the edges further and nothing bends away from the neighbours' planes); cube and wedges optima.
constexpr double kFlatEdgesSigmaF = 6.5;
constexpr int kFlatEdgesPasses = 8;
// Curved faces between edges: sigma_f grows with the noise, since more neighbours average more of
// it, but starts narrow, since a neighbour's plane leaves a curved surface quadratically with the
// distance (fandisk and cylinder optima: 1.6 spacings clean, 3-4 at p = 0.25-0.5, 12 at 2) ...
constexpr double kCurvedEdgesSigmaF0 = 1.6;
constexpr double kCurvedEdgesSigmaFPerNoise = 5.0;
constexpr double kCurvedEdgesSigmaFMax = 12.0;
// ... and the passes fall with the noise: later passes drift on curved patches and eat small
// features (fandisk: 8 clean, 2 at p = 0.4; the cylinder: 4 at p = 0.26). passes = this / p,
// between the bounds below.
constexpr double kCurvedEdgesPassesTimesNoise = 1.1;
constexpr int kCurvedEdgesMinPasses = 2;
constexpr int kCurvedEdgesMaxPasses = 8;
// Smooth shapes: the feature term off ("off": a width so large that exp(-d^2 / 2 sigma_g^2) is 1
// to double precision for any neighbour within 2 sigma_f <= 24 spacings) and a wide sigma_f.
constexpr double kSigmaGOff = 1e6;
constexpr double kSmoothSigmaF = 8.0;
// A smooth flat shape (a plane) gains from every pass.
constexpr int kSmoothFlatPasses = 8;
// A smooth curved one loses a little with each pass (the averaged normals lean towards the
// denser side of an irregular sample), so the passes follow the angular noise of the input:
// none when the positions are clean and the normals already agree with the fitted surface to
// within this (clean spheres: the input was the best of the grid; at 0.1 spacings of noise one
// pass still gained 15%) ...
constexpr double kNoFilterNormalNoiseDeg = 0.6;
constexpr double kNoFilterNoise = 0.05;
// ... one pass up to this, then two (spheres and tori, PCA-16 against PCA-64 input normals).
constexpr double kOnePassNormalNoiseDeg = 3.0;
constexpr int kSmoothCurvedPasses = 2;
// Clean positions, but input normals whose errors are alike over a few spacings (normal error
// correlation from this up; already smoothed, as PCA over 64 neighbours): averaging them again
// keeps their errors, while the feature term with sigma_g 0.2 spacings (kSigmaG0) re-derives the
// normals from the positions. One pass, sigma_f between the neighbours' reach and the curvature's
// (clean torus, PCA-64: 0.70 deg at 3.3 spacings against 0.83 at 1.6 and 0.89 at 6.6, input 1.10;
// PCA-16 normals there, correlation 0.06, need plain averaging). Clean spheres and tori measured
// 0.02-0.06 with PCA-16 normals, 0.18-0.34 with PCA-64.
constexpr double kCoherentErrorCorrelation = 0.2;
constexpr double kCoherentSigmaF = 3.3;
// Past this noise (spacings) the feature term rejects more of the same surface than of the other
// side of an edge, and the estimates can no longer see the edges: it is switched off and the
// normals are so poor that averaging keeps paying (fandisk at 1.2% of its diagonal: 8.5-9
// spacings with 10-16 passes all land within 0.01 degrees of each other).
constexpr double kFeatureOffNoise = 3.0;
constexpr double kTooNoisySigmaF = 8.5;
constexpr int kTooNoisyPasses = 14;
// Passes also end when the normals move less than this on average. Small: on flat shapes every
// pass still gains a little (at 0.1 degrees the plane and cube stopped at 3-5 of their 8 passes
// and lost 10-25%).
constexpr double kStopChangeDeg = 0.01;

using Tree = flann::KDTreeSingleIndex<flann::L2<double>>;

using detail::bounding_box;

void check_cloud(const PointCloud& cloud) {
  constexpr std::size_t kMinPoints = 16;
  if (cloud.size() < kMinPoints) {
    throw Error(ErrorCode::invalid_input, "estimate_data: need at least " + std::to_string(kMinPoints) +
                                              " points, got " + std::to_string(cloud.size()));
  }
  if (cloud.has_normals() && cloud.normals.size() != cloud.size()) {
    throw Error(ErrorCode::invalid_input, "estimate_data: " + std::to_string(cloud.normals.size()) + " normals for " +
                                              std::to_string(cloud.size()) + " points");
  }
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3& p = cloud.positions[i];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      throw Error(ErrorCode::invalid_input,
                  "estimate_data: vertex " + std::to_string(i) + " has a non-finite coordinate");
    }
  }
}

// One sample's fit at one scale.
struct SampleFit {
  bool ok = false;
  double spacing = 0;     // sqrt(pi rho^2 / count in the cylinder)
  double residual = 0;    // RMS distance to the quadric, corrected for the 6 fitted coefficients
  double angle_deg = -1;  // input normal vs quadric normal at the sample, as lines
  double radius = 0;      // rho
  double curvature = 0;   // the quadric's largest principal curvature magnitude, 1 / model units
  // Sums over the points within kCorrelationReachSpacings of the sample, of e_sample . e_point
  // and |e_sample| |e_point|, e being an input normal minus the quadric's normal at that point.
  double error_dot = 0;
  double error_magnitudes = 0;
};

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  auto middle = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// Fits the neighbourhood `ids` (the sample itself included) of sample `self`: a PCA frame, then
// a quadric height field w(u, v) over the points of the cylinder of radius
// kCylinderFraction * (distance to the farthest neighbour) around the frame's axis through the
// sample. The cylinder is symmetric about the sample, so the quadric's slope there is not biased
// by curvature (the even terms are orthogonal to the odd ones). With normals, also compares the
// input normals with the quadric's: at the sample (angle_deg) and, for the correlation of the
// errors, at the points near it.
SampleFit fit_sample(const std::vector<double>& centred, const PointCloud& cloud, std::size_t self,
                     const std::size_t* ids, const double* squared_distances, int count) {
  SampleFit fit;
  const Eigen::Vector3d origin(centred[self * 3], centred[self * 3 + 1], centred[self * 3 + 2]);
  std::vector<Eigen::Vector3d> offsets(static_cast<std::size_t>(count));
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double farthest_squared = 0;
  for (int k = 0; k < count; ++k) {
    const std::size_t id = ids[k];
    offsets[std::size_t(k)] = Eigen::Vector3d(centred[id * 3], centred[id * 3 + 1], centred[id * 3 + 2]) - origin;
    centroid += offsets[std::size_t(k)];
    farthest_squared = std::max(farthest_squared, squared_distances[k]);  // FLANN's L2 is squared
  }
  centroid /= double(count);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& o : offsets) covariance += (o - centroid) * (o - centroid).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  const Eigen::Vector3d normal = eigen.eigenvectors().col(0);
  const Eigen::Vector3d t1 = eigen.eigenvectors().col(2);
  const Eigen::Vector3d t2 = normal.cross(t1);
  const double rho = kCylinderFraction * std::sqrt(farthest_squared);
  if (!(rho > 0) || !(eigen.eigenvalues()(1) > 0)) return fit;

  // Least squares in coordinates relative to the sample, scaled by rho (well conditioned at any
  // model scale).
  Eigen::Matrix<double, 6, 6> normal_matrix = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> rhs = Eigen::Matrix<double, 6, 1>::Zero();
  std::vector<Eigen::Vector3d> local;
  local.reserve(offsets.size());
  for (const Eigen::Vector3d& o : offsets) {
    const double u = o.dot(t1) / rho, v = o.dot(t2) / rho;
    if (u * u + v * v > 1.0) continue;
    const double w = o.dot(normal) / rho;
    local.emplace_back(u, v, w);
    Eigen::Matrix<double, 6, 1> row;
    row << 1, u, v, u * u, u * v, v * v;
    normal_matrix += row * row.transpose();
    rhs += row * w;
  }
  const int fitted = int(local.size());
  if (fitted < kMinFitPoints) return fit;
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> solver = normal_matrix.ldlt();
  const Eigen::Matrix<double, 6, 1> c = solver.solve(rhs);
  double rss = 0;
  for (const Eigen::Vector3d& q : local) {
    const double model =
        c(0) + c(1) * q.x() + c(2) * q.y() + c(3) * q.x() * q.x() + c(4) * q.x() * q.y() + c(5) * q.y() * q.y();
    rss += (q.z() - model) * (q.z() - model);
  }
  fit.ok = std::isfinite(rss);
  fit.radius = rho;
  fit.residual = rho * std::sqrt(rss / double(fitted - 6));
  fit.spacing = std::sqrt(kPi * rho * rho / double(fitted));
  {
    // Hessian of the height field in model units: the fit is in units of rho.
    const double a = 2 * c(3) / rho, b = c(4) / rho, d = 2 * c(5) / rho;
    fit.curvature = std::abs(0.5 * (a + d)) + std::sqrt(0.25 * (a - d) * (a - d) + b * b);
  }
  if (cloud.has_normals()) {
    // The quadric's unit normal at (u, v) (in units of rho), and the input normal of point `id`
    // as a unit vector on the same side, or zero when it has no direction.
    auto surface_at = [&](double u, double v) {
      return (normal - (c(1) + 2 * c(3) * u + c(4) * v) * t1 - (c(2) + c(4) * u + 2 * c(5) * v) * t2).normalized();
    };
    auto input_towards = [&](std::size_t id, const Eigen::Vector3d& side) -> Eigen::Vector3d {
      const Vec3& n = cloud.normals[id];
      const Eigen::Vector3d input(n[0], n[1], n[2]);
      const double length = input.norm();
      if (!(length > 0) || !std::isfinite(length)) return Eigen::Vector3d::Zero();
      return input.dot(side) < 0 ? Eigen::Vector3d(-input / length) : Eigen::Vector3d(input / length);
    };
    const Eigen::Vector3d surface = surface_at(0, 0);
    const Eigen::Vector3d input = input_towards(self, surface);
    if (input.squaredNorm() > 0) {
      const double cosine = std::min(1.0, surface.dot(input));
      fit.angle_deg = std::atan2(surface.cross(input).norm(), cosine) * 180.0 / kPi;
      const Eigen::Vector3d error = input - surface;
      const double reach = kCorrelationReachSpacings * fit.spacing;
      for (int k = 0; k < count; ++k) {
        if (ids[k] == self) continue;
        const Eigen::Vector3d& o = offsets[std::size_t(k)];
        const double u = o.dot(t1), v = o.dot(t2);
        if (u * u + v * v > reach * reach) continue;
        const Eigen::Vector3d there = surface_at(u / rho, v / rho);
        const Eigen::Vector3d other = input_towards(ids[k], there);
        if (other.squaredNorm() == 0) continue;
        fit.error_dot += error.dot(other - there);
        fit.error_magnitudes += error.norm() * (other - there).norm();
      }
    }
  }
  return fit;
}

std::string format(const char* pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

}  // namespace

DataEstimate estimate_data(const PointCloud& cloud) {
  check_cloud(cloud);
  const std::size_t count = cloud.size();
  // Coordinates relative to the bounding-box centre: a far-away scan loses no digits in the fits.
  const detail::BoundingBox box = bounding_box(cloud.positions);
  std::vector<double> centred(count * 3);
  for (std::size_t i = 0; i < count; ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      centred[i * 3 + axis] = cloud.positions[i][axis] - 0.5 * (box.low[axis] + box.high[axis]);
    }
  }
  const flann::Matrix<double> points(centred.data(), count, 3);
  Tree tree(points, flann::KDTreeSingleIndexParams(10));
  tree.buildIndex();
  flann::SearchParams search;
  search.checks = flann::FLANN_CHECKS_UNLIMITED;
  search.eps = 0.0f;
  search.sorted = false;
  search.cores = 1;  // the samples are spread over threads below instead

  // Fits every sample at one scale, in parallel.
  auto fit_scale = [&](int scale) {
    const int neighbours = int(std::min<std::size_t>(std::size_t(scale), count - 1)) + 1;  // the sample too
    const std::size_t samples =
        std::min({count, kMaxSamples, std::max<std::size_t>(1, kMaxLookupsPerScale / std::size_t(neighbours))});
    std::vector<SampleFit> fits(samples);
#pragma omp parallel
    {
      std::vector<std::size_t> ids(static_cast<std::size_t>(neighbours));
      std::vector<double> distances(static_cast<std::size_t>(neighbours));
#pragma omp for schedule(dynamic, 16)
      for (long long s = 0; s < static_cast<long long>(samples); ++s) {
        // Evenly spread, deterministic: sample s is point floor(s N / samples).
        const std::size_t self = std::size_t(s) * count / samples;
        flann::Matrix<double> query(centred.data() + self * 3, 1, 3);
        flann::Matrix<std::size_t> id_matrix(ids.data(), 1, std::size_t(neighbours));
        flann::Matrix<double> distance_matrix(distances.data(), 1, std::size_t(neighbours));
        tree.knnSearch(query, id_matrix, distance_matrix, std::size_t(neighbours), search);
        fits[std::size_t(s)] = fit_sample(centred, cloud, self, ids.data(), distances.data(), neighbours);
      }
    }
    fits.erase(std::remove_if(fits.begin(), fits.end(), [](const SampleFit& f) { return !f.ok; }), fits.end());
    return fits;
  };
  auto medians = [](const std::vector<SampleFit>& fits, double SampleFit::*field) {
    std::vector<double> values;
    for (const SampleFit& f : fits) values.push_back(f.*field);
    return median(values);
  };

  // Noise and spacing at the smallest trusted scale.
  DataEstimate estimate;
  estimate.points = count;
  const int scales = int(std::size(kScales));
  int chosen = -1;
  for (int i = 0; i < scales; ++i) {
    const std::vector<SampleFit> fits = fit_scale(kScales[i]);
    if (fits.empty()) continue;
    chosen = i;
    estimate.samples = fits.size();
    estimate.spacing = medians(fits, &SampleFit::spacing);
    estimate.position_noise = medians(fits, &SampleFit::residual);
    estimate.fit_neighbours = int(std::min<std::size_t>(std::size_t(kScales[i]), count - 1));
    estimate.fit_radius = medians(fits, &SampleFit::radius);
    if (estimate.position_noise <= kMaxNoiseToFitRadius * estimate.fit_radius) break;
    if (std::size_t(kScales[i]) >= count - 1) break;  // no larger neighbourhood exists
  }
  if (chosen < 0) {
    throw Error(
        ErrorCode::invalid_input,
        "estimate_data: no neighbourhood could be fitted with a surface (are the points on a line or one spot?)");
  }
  // Features and normals are judged on the fits two scales up (16 times the points, twice the
  // radius). There a sharp edge inside the cylinder leaves a residual well above the noise, and
  // the quadric's slope moves with the noise a quarter as much as at the noise scale. The fits
  // hold many more points than a PCA normal of up to ~100 neighbours, whose errors are then
  // nearly independent of theirs (a correction in quadrature would need that independence; two
  // scales up it is not needed).
  const double edge_residual =
      kEdgeResidualPerNoise * std::max(estimate.position_noise, kResidualFloorPerSpacing * estimate.spacing);
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
  // Curvature is judged only on fits that are clearly smooth (residual within the noise's own
  // spread): a fit grazing an edge reports a large curvature.
  const double smooth_residual =
      kSmoothResidualPerNoise * std::max(estimate.position_noise, kResidualFloorPerSpacing * estimate.spacing);
  std::size_t smooth = 0, curved = 0;
  for (const SampleFit& f : fits) {
    if (f.residual > smooth_residual) continue;
    ++smooth;
    curved += f.curvature * estimate.spacing > kCurvedPerSpacing;
  }
  estimate.curved_share = double(curved) / double(std::max<std::size_t>(1, smooth));
  if (cloud.has_normals()) {
    estimate.normal_noise_deg = medians(fits, &SampleFit::angle_deg) * kRayleighRmsPerMedian;
    // The reference is the quadric two scales up (one where the step-down above was taken),
    // fitted to 16 times the points of a PCA normal of 64 neighbours: at the noise scale the fit
    // shares the input normals' neighbours and with them most of their errors, and the
    // correlation measured there was near 0 for PCA-16 and PCA-64 alike.
    double dot = 0, magnitudes = 0;
    for (const SampleFit& f : fits) {
      dot += f.error_dot;
      magnitudes += f.error_magnitudes;
    }
    estimate.normal_error_correlation = magnitudes > 0 ? dot / magnitudes : 0;
  }
  return estimate;
}

AutoChoice choose_filter_params(const DataEstimate& estimate) {
  if (!(estimate.spacing > 0) || !std::isfinite(estimate.spacing)) {
    throw Error(ErrorCode::invalid_argument,
                "choose_filter_params: spacing must be > 0 and finite, got " + format("%g", estimate.spacing));
  }
  const double noise = estimate.position_noise_spacings();
  AutoChoice choice;
  choice.estimate = estimate;
  FilterParams& p = choice.params;
  p.units = Units::radius;
  p.mean_radius = estimate.spacing;
  p.stop_change_deg = kStopChangeDeg;
  const bool smooth = estimate.feature_share < kSmoothShare;
  const bool curved = estimate.curved_share >= kCurvedShare;
  const double normal_noise = estimate.normal_noise_deg;
  std::string why = (smooth ? "smooth (features " : "edges (features ") + format("%.0f", 100 * estimate.feature_share) +
                    "%), " + (curved ? "curved (" : "flat (") + format("%.0f", 100 * estimate.curved_share) +
                    "% curved)";
  if (noise > kFeatureOffNoise) {
    p.sigma_f = kTooNoisySigmaF;
    p.sigma_g = kSigmaGOff;
    p.iterations = kTooNoisyPasses;
    why = "too noisy for features (> " + format("%g", kFeatureOffNoise) + " spacings)";
  } else if (smooth) {
    p.sigma_f = kSmoothSigmaF;
    p.sigma_g = kSigmaGOff;
    if (!curved) {
      p.iterations = kSmoothFlatPasses;
    } else if (normal_noise < 0) {  // no input normals to judge: the noisy case
      p.iterations = kSmoothCurvedPasses;
    } else if (noise < kNoFilterNoise && normal_noise < kNoFilterNormalNoiseDeg) {
      p.iterations = 0;
      why += ", normals already agree with the surface";
    } else if (noise < kNoFilterNoise && estimate.normal_error_correlation >= kCoherentErrorCorrelation) {
      p.sigma_f = kCoherentSigmaF;
      p.sigma_g = kSigmaG0 + kSigmaGPerNoise * noise;
      p.iterations = 1;
      why += ", clean positions, normal errors alike over spacings (correlation " +
             format("%.2f", estimate.normal_error_correlation) + ")";
    } else {
      p.iterations = normal_noise < kOnePassNormalNoiseDeg ? 1 : kSmoothCurvedPasses;
    }
  } else {
    p.sigma_g = kSigmaG0 + kSigmaGPerNoise * noise;
    if (!curved) {
      p.sigma_f = kFlatEdgesSigmaF;
      p.iterations = kFlatEdgesPasses;
    } else {
      p.sigma_f = std::min(kCurvedEdgesSigmaF0 + kCurvedEdgesSigmaFPerNoise * noise, kCurvedEdgesSigmaFMax);
      const double passes = noise > 0 ? kCurvedEdgesPassesTimesNoise / noise : kCurvedEdgesMaxPasses;
      p.iterations = int(std::clamp(std::floor(passes), double(kCurvedEdgesMinPasses), double(kCurvedEdgesMaxPasses)));
    }
  }
  const bool feature_off = p.sigma_g >= kSigmaGOff;
  std::ostringstream rule;
  rule << "noise " << format("%.3g", noise) << " spacings";
  if (estimate.normal_noise_deg >= 0) rule << ", normals " << format("%.3g", estimate.normal_noise_deg) << " deg";
  rule << ", " << why << " -> ";
  if (p.iterations == 0) {
    rule << "no pass (the input normals are kept)";
  } else {
    rule << "sigma_f " << format("%.3g", p.sigma_f) << ", sigma_g "
         << (feature_off ? std::string("off") : format("%.3g", p.sigma_g)) << " spacings, up to " << p.iterations
         << " passes, stop below " << format("%g", p.stop_change_deg) << " deg";
  }
  choice.rule = rule.str();
  return choice;
}

AutoChoice choose_filter_params(const PointCloud& cloud) { return choose_filter_params(estimate_data(cloud)); }

}  // namespace pnf
