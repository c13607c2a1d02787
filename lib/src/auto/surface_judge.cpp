// --auto's judge of a normal field against the surface its positions carry (surface_judge.hpp).
#include "surface_judge.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "geometry.hpp"
#include "quadric_moments.hpp"
#include "sample_neighbourhoods.hpp"
#include "vector_exp.hpp"

namespace pnf::detail {
namespace {

// Reweighting steps of the fit: from the judged normal's own plane, the weights settle on one
// sheet within a few steps (the score moved by under 1% after the fifth on the real meshes).
constexpr int kReweightSteps = 5;
// A quadric has 6 coefficients; twice as many points at least.
constexpr int kMinNeighbours = 12;
// The fewest points choose_scale fits to stay under the input's support: at 16 the reweighted
// quadric's slope variance read the judge's own error at 2-76 degrees on the clean real meshes
// (docs/auto.md, "Fits finer than the input's support").
constexpr int kFinestFit = 32;
// The supports input_support tries: 16 points, then doubling up to the whole neighbourhood.
constexpr int kSmallestSupport = 16;
// plane_fit_count: the fewest points that make a plane, and how near (RMS over the samples,
// degrees) input normals must be to the planes of their nearest points to be those planes. Normals
// stored as floats round by about 1e-5 degrees; on the real meshes' clean rows the PCA normals sat
// 1e-14 degrees from their own count's planes, the exact normals 1.2-16 degrees from every plane
// tried (docs/auto.md, "The narrow pass for plane-fit normals").
constexpr int kFewestPlanePoints = 3;
constexpr double kPlaneFitToleranceDeg = 1e-3;

// Calls at(k, covariance) for each count k = 1, 2, ... `count` of a sample's nearest points
// (`offsets`, nearest first, x y z rows), their covariance from running sums.
template <class AtCount>
void for_each_nearest_count(const double* offsets, int count, AtCount&& at) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
  for (int j = 0; j < count; ++j) {
    const Eigen::Vector3d x(offsets[3 * j], offsets[3 * j + 1], offsets[3 * j + 2]);
    sum += x;
    outer += x * x.transpose();
    const Eigen::Vector3d mean = sum / double(j + 1);
    at(j + 1, Eigen::Matrix3d(outer / double(j + 1) - mean * mean.transpose()));
  }
}

// The angle (radians) between `n` and the plane normal of `covariance` (its least axis), as lines.
double angle_to_plane(const Eigen::Vector3d& n, const Eigen::Matrix3d& covariance) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  const Eigen::Vector3d plane = eigen.eigenvectors().col(0);
  const double angle = geometry::angle_radians({n.x(), n.y(), n.z()}, {plane.x(), plane.y(), plane.z()});
  return std::min(angle, geometry::kPi - angle);
}

// The angle (radians) between `n` and the normal of the quadric fitted in n's frame to the
// sample's neighbours (`offsets`, `count` rows), each weighted by a Gaussian of width `width` on
// its residual, starting from the residual to n's plane.
struct FrameError {
  double angle = 0;                 // radians
  double slope_u = 0, slope_v = 0;  // the fitted surface's slope along the frame's tangents
  double variance = 0;              // of the slope, from the weighted residuals (radians^2)
};

// A neighbourhood in the judged normal's frame, one array per coordinate (the fits' loops read
// them in step): tangent coordinates u, v and height h, in units of the farthest neighbour.
struct FramePoints {
  std::vector<double> u, v, h, weights;
  void resize(std::size_t count) {
    u.resize(count);
    v.resize(count);
    h.resize(count);
    weights.resize(count);
  }
};

// The quadric's coefficients c (height = c0 + c1 u + c2 v + c3 u^2 + c4 uv + c5 v^2) by weighted
// least squares, with m = A^T W A (quadric_moments.hpp).
QuadricVector weighted_fit(const FramePoints& p, std::size_t count, QuadricMatrix& m) {
  double s[kQuadricMoments];
  quadric_moment_sums(p.weights.data(), p.u.data(), p.v.data(), p.h.data(), count, s);
  m = quadric_normal_matrix(s);
  m.diagonal().array() += 1e-12;
  return m.ldlt().solve(quadric_right_side(s));
}

double residual(const FramePoints& p, std::size_t k, const QuadricVector& c) {
  return p.h[k] - quadric_height(c, p.u[k], p.v[k]);
}

// Each point weighted by a Gaussian of its residual to the quadric `c`, of width `w_scale`: the
// exponents first, then exp over them all at once (vector_exp.hpp).
void reweight(FramePoints& p, std::size_t count, const QuadricVector& c, double w_scale) {
  for (std::size_t k = 0; k < count; ++k) {
    const double r = residual(p, k, c) / w_scale;
    p.weights[k] = -0.5 * r * r;
  }
  exp_in_place(p.weights.data(), count);
}

// Without `with_variance` only the angle and slopes are computed: the last reweighting and the
// variance serve only the judge's own error, and a pass's score needs neither.
FrameError error_in_frame(const double* offsets, int count, Eigen::Vector3d n, double width, bool with_variance) {
  const double length = n.norm();
  if (!(length > 0) || !std::isfinite(length)) return {};
  n /= length;
  Vec3 a, b;
  geometry::tangent_basis({n.x(), n.y(), n.z()}, a, b);
  const Eigen::Vector3d t1(a[0], a[1], a[2]), t2(b[0], b[1], b[2]);
  // Coordinates in units of the farthest neighbour, for a well-conditioned system.
  double reach = 0;
  for (int k = 0; k < count; ++k) {
    const Eigen::Vector3d o(offsets[3 * k], offsets[3 * k + 1], offsets[3 * k + 2]);
    reach = std::max(reach, o.norm());
  }
  if (!(reach > 0)) return {};
  const double w_scale = width / reach;
  const std::size_t points = std::size_t(count);
  thread_local FramePoints p;  // one neighbourhood at a time per thread: no allocation per fit
  p.resize(points);
  for (std::size_t k = 0; k < points; ++k) {
    const Eigen::Vector3d o = Eigen::Vector3d(offsets[3 * k], offsets[3 * k + 1], offsets[3 * k + 2]) / reach;
    p.u[k] = o.dot(t1);
    p.v[k] = o.dot(t2);
    p.h[k] = o.dot(n);
  }
  // The first weights from the residuals to n's plane: those to the quadric 0.
  QuadricVector c = QuadricVector::Zero();
  QuadricMatrix m;
  for (int step = 0; step < kReweightSteps; ++step) {
    reweight(p, points, c, w_scale);
    c = weighted_fit(p, points, m);
  }
  // The weights of the fit found: for the variance only.
  if (with_variance) reweight(p, points, c, w_scale);
  const double slope = std::hypot(c(1), c(2));
  if (!std::isfinite(slope)) return {};
  if (!with_variance) return {std::atan(slope), c(1), c(2), 0.0};
  // The slope's variance: the weighted residuals' variance times (A^T W A)^-1's slope terms.
  double rss = 0, weight = 0;
  for (std::size_t k = 0; k < points; ++k) {
    const double r = residual(p, k, c);
    rss += p.weights[k] * r * r;
    weight += p.weights[k];
  }
  const QuadricMatrix inverse = m.inverse();
  const double variance = weight > 6 ? rss / (weight - 6) * (inverse(1, 1) + inverse(2, 2)) : 0.0;
  return {std::atan(slope), c(1), c(2), std::isfinite(variance) ? variance : 0.0};
}

}  // namespace

SurfaceJudge::SurfaceJudge(const std::vector<double>& centred, const SampleNeighbourhoods& neighbourhoods, double width)
    : width_(width) {
  neighbours_ = neighbourhoods.neighbours;
  scored_ = neighbours_;
  const std::size_t samples = neighbourhoods.samples(), k = std::size_t(neighbours_);
  if (samples == 0 || neighbours_ < kMinNeighbours || !(width > 0)) return;
  ids_ = neighbourhoods.selves;
  offsets_.resize(samples * k * 3);
  // Nearest first, so that the first quarter of the rows is the next scale down's neighbourhood.
  for (std::size_t s = 0; s < samples; ++s) {
    const std::size_t self = ids_[s];
    const std::size_t* ids = neighbourhoods.ids_of(s);
    double* out = &offsets_[s * k * 3];
    for (std::size_t j = 0; j < k; ++j) {
      for (int axis = 0; axis < 3; ++axis) out[3 * j + axis] = centred[ids[j] * 3 + axis] - centred[self * 3 + axis];
    }
  }
}

// The per-sample terms are kept and summed in sample order afterwards, not reduced across
// threads, so that a judge's score has the same bits on any thread count and schedule (one
// process and a distributed run's rank 0 agree; issue 31).
SurfaceJudge::Sums SurfaceJudge::sums(const double* normals_xyz) const {
  Sums sums;
  if (empty()) return sums;
  sums.samples = ids_.size();
  const std::size_t k = std::size_t(neighbours_), samples = ids_.size();
  // The next scale down: a quarter of the scored neighbours, the nearest.
  const int inner = scored_ / 4;
  std::vector<double> squared(samples, 0.0), variance(samples, 0.0), inner_variance(samples, 0.0);
  std::vector<double> apart(samples, 0.0);
#pragma omp parallel for schedule(dynamic, 16)
  for (long long s = 0; s < static_cast<long long>(samples); ++s) {
    const std::size_t i = ids_[std::size_t(s)];
    const Eigen::Vector3d n(normals_xyz[3 * i], normals_xyz[3 * i + 1], normals_xyz[3 * i + 2]);
    const double* offsets = &offsets_[std::size_t(s) * k * 3];
    const FrameError e = error_in_frame(offsets, scored_, n, width_, true);
    squared[std::size_t(s)] = e.angle * e.angle;
    variance[std::size_t(s)] = e.variance;
    if (inner >= kMinNeighbours) {
      const FrameError near = error_in_frame(offsets, inner, n, width_, true);
      const double a = std::atan(std::hypot(e.slope_u - near.slope_u, e.slope_v - near.slope_v));
      apart[std::size_t(s)] = a * a;
      inner_variance[std::size_t(s)] = near.variance;
    }
  }
  // The median, not the mean: the fits at a sharp edge hold on to different faces at the two
  // scales, and the minority of samples there would read as an uncertain judge everywhere. The
  // squared distance of two Gaussian slopes is exponential, mean = median / ln 2.
  auto middle = apart.begin() + std::ptrdiff_t(samples / 2);
  std::nth_element(apart.begin(), middle, apart.end());
  sums.squared = std::accumulate(squared.begin(), squared.end(), 0.0);
  sums.variance = std::accumulate(variance.begin(), variance.end(), 0.0);
  sums.inner_variance = std::accumulate(inner_variance.begin(), inner_variance.end(), 0.0);
  sums.disagreement = double(samples) * *middle / std::log(2.0);
  return sums;
}

double SurfaceJudge::sum_squared(const double* normals_xyz) const {
  if (empty()) return 0;
  const std::size_t k = std::size_t(neighbours_);
  std::vector<double> squared(ids_.size(), 0.0);
#pragma omp parallel for schedule(dynamic, 16)
  for (long long s = 0; s < static_cast<long long>(ids_.size()); ++s) {
    const std::size_t i = ids_[std::size_t(s)];
    const Eigen::Vector3d n(normals_xyz[3 * i], normals_xyz[3 * i + 1], normals_xyz[3 * i + 2]);
    const double a = error_in_frame(&offsets_[std::size_t(s) * k * 3], scored_, n, width_, false).angle;
    squared[std::size_t(s)] = a * a;
  }
  return std::accumulate(squared.begin(), squared.end(), 0.0);
}

double SurfaceJudge::rms_deg(const double* normals_xyz) const {
  if (empty()) return 0;
  return std::sqrt(sum_squared(normals_xyz) / double(ids_.size())) * 180 / geometry::kPi;
}

double SurfaceJudge::Sums::rms_deg() const {
  return samples > 0 ? std::sqrt(squared / double(samples)) * 180 / geometry::kPi : 0.0;
}

double SurfaceJudge::Sums::own_error_deg() const {
  return samples > 0 ? std::sqrt(own_error_squared() / double(samples)) * 180 / geometry::kPi : 0.0;
}

double SurfaceJudge::Sums::own_error_squared() const {
  // The fits' noise, and what of the two scales' disagreement their noise does not explain: the
  // bias of detail finer than the neighbourhood, or of a sheet the weights lost.
  return variance + std::max(disagreement - variance - inner_variance, 0.0);
}

std::vector<int> SurfaceJudge::scales_of(int neighbours) {
  // The quarter's own next scale down, a sixteenth, must hold a fit for its own error.
  if (neighbours / 16 < kMinNeighbours) return {neighbours};
  return {neighbours, neighbours / 4};
}

bool SurfaceJudge::quarter_is_better(const Sums& whole, const Sums& quarter) {
  return quarter.own_error_squared() < whole.own_error_squared();
}

int SurfaceJudge::input_support(const double* normals_xyz) const {
  std::vector<int> supports;
  for (int k = kSmallestSupport; k <= neighbours_; k *= 2) supports.push_back(k);
  if (empty() || supports.empty()) return 0;
  const std::size_t samples = ids_.size(), count = supports.size(), k = std::size_t(neighbours_);
  // Per sample, then summed in sample order: the same bits on any thread count (as in sums).
  std::vector<double> squared(samples * count, 0.0);
#pragma omp parallel for schedule(dynamic, 16)
  for (long long s = 0; s < static_cast<long long>(samples); ++s) {
    const std::size_t i = ids_[std::size_t(s)];
    const Eigen::Vector3d n(normals_xyz[3 * i], normals_xyz[3 * i + 1], normals_xyz[3 * i + 2]);
    std::size_t next = 0;
    for_each_nearest_count(&offsets_[std::size_t(s) * k * 3], supports.back(),
                           [&](int points, const Eigen::Matrix3d& c) {
                             if (points != supports[next]) return;
                             const double angle = angle_to_plane(n, c);
                             squared[std::size_t(s) * count + next++] = angle * angle;
                           });
  }
  std::vector<double> total(count, 0.0);
  for (std::size_t s = 0; s < samples; ++s) {
    for (std::size_t c = 0; c < count; ++c) total[c] += squared[s * count + c];
  }
  const std::size_t closest = std::size_t(std::min_element(total.begin(), total.end()) - total.begin());
  // The widest plane tried is also the nearest to normals truer than any (exact ones on a noisy
  // plane): no support can be told there.
  return closest + 1 < count ? supports[closest] : 0;
}

int SurfaceJudge::plane_fit_count(const double* normals_xyz) const {
  if (empty() || neighbours_ < kFewestPlanePoints) return 0;
  const std::size_t samples = ids_.size(), k = std::size_t(neighbours_);
  // How far each normal is from being an axis of each count's covariance, |C n - (n.C n) n|^2 over
  // trace(C)^2 (0 on an axis; a matrix product per count, so every count can be tried), per sample
  // and count, then summed in sample order: the same bits on any thread count.
  std::vector<double> off_axis(samples * k, 0.0);
#pragma omp parallel for schedule(dynamic, 16)
  for (long long s = 0; s < static_cast<long long>(samples); ++s) {
    const std::size_t i = ids_[std::size_t(s)];
    const Eigen::Vector3d n(normals_xyz[3 * i], normals_xyz[3 * i + 1], normals_xyz[3 * i + 2]);
    for_each_nearest_count(&offsets_[std::size_t(s) * k * 3], neighbours_, [&](int points, const Eigen::Matrix3d& c) {
      const Eigen::Vector3d product = c * n;
      const double trace = c.trace();
      off_axis[std::size_t(s) * k + std::size_t(points) - 1] =
          trace > 0 ? (product - n.dot(product) * n).squaredNorm() / (trace * trace) : 0.0;
    });
  }
  std::vector<double> total(k, 0.0);
  for (std::size_t s = 0; s < samples; ++s) {
    for (std::size_t c = 0; c < k; ++c) total[c] += off_axis[s * k + c];
  }
  const auto fewest = total.begin() + (kFewestPlanePoints - 1);
  const int count = int(std::min_element(fewest, total.end()) - total.begin()) + 1;
  // The normals are the planes of that count only if each is its covariance's least axis.
  std::vector<double> squared(samples, 0.0);
#pragma omp parallel for schedule(dynamic, 16)
  for (long long s = 0; s < static_cast<long long>(samples); ++s) {
    const std::size_t i = ids_[std::size_t(s)];
    const Eigen::Vector3d n(normals_xyz[3 * i], normals_xyz[3 * i + 1], normals_xyz[3 * i + 2]);
    for_each_nearest_count(&offsets_[std::size_t(s) * k * 3], count, [&](int points, const Eigen::Matrix3d& c) {
      if (points == count) squared[std::size_t(s)] = std::pow(angle_to_plane(n, c), 2);
    });
  }
  double sum = 0;
  for (double a : squared) sum += a;
  return std::sqrt(sum / double(samples)) * 180 / geometry::kPi <= kPlaneFitToleranceDeg ? count : 0;
}

void SurfaceJudge::choose_scale(const double* normals_xyz) {
  if (empty()) return;
  plane_fits_ = plane_fit_count(normals_xyz);
  std::vector<int> candidates = scales_of(neighbours_);
  // Fits that hold no more than half of the points each input normal follows, so that they do
  // not share its smoothing; where the judge cannot fit so few, as before.
  const int support = input_support(normals_xyz);
  if (support / 2 >= kFinestFit) {
    under_support_ = support;
    candidates.erase(std::remove_if(candidates.begin(), candidates.end(), [&](int c) { return c > support / 2; }),
                     candidates.end());
    if (candidates.empty()) candidates.push_back(support / 2);
  }
  if (candidates.size() < 2) {
    score_with(candidates[0]);
    input_sums_ = sums(normals_xyz);
    return;
  }
  score_with(candidates[0]);
  const Sums whole = sums(normals_xyz);
  score_with(candidates[1]);
  const Sums quarter = sums(normals_xyz);
  const bool quarter_better = quarter_is_better(whole, quarter);
  if (!quarter_better) score_with(candidates[0]);
  input_sums_ = quarter_better ? quarter : whole;
}

double SurfaceJudge::own_error_deg(const double* normals_xyz) const { return sums(normals_xyz).own_error_deg(); }

}  // namespace pnf::detail
