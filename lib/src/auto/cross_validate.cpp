// --auto's cross-validation (cross_validate.hpp).
#include "cross_validate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "cloud_checks.hpp"
#include "filter_factory.hpp"
#include "geometry.hpp"
#include "pnf/bounding_box.hpp"
#include "pnf/error.hpp"
#include "pnf_filter.h"
#include "setting_grid.hpp"
#include "spatial/spatial_index.hpp"

namespace pnf::detail {
namespace {

// An eighth of the points held out: the rest keeps 7/8 of the density (the settings' lengths are
// in model units, so a sparser rest would favour wider ones). Every setting is scored on the
// same points, so the input's own error, the bulk of each score, is common to all; what remains
// is noise of about 2 x input error x the settings' difference / sqrt(held), and the differences
// that matter shrink as the density grows (the creases' share falls): 8000 held-out points at
// 100k picked 0.68 deg instead of the best 0.57 on one draw of the 90-degree crease with 8-degree
// tilts, 12500 picked 0.57 on all three draws tried.
constexpr double kHeldOutShare = 0.125;
// ... and at most this many (an eighth of 400k points), so that the held-out passes, run on the
// CPU in double, cost at most about as much as the settings' runs on the rest; beyond it the rest
// is denser than 7/8.
constexpr std::size_t kMaxHeldOut = 50000;
// Points whose divergence is measured (HeldOutPasses).
constexpr std::size_t kNudgedPoints = 4000;
// Smaller clouds are cross-validated over several disjoint held-out eighths (folds), up to this
// many, until this many points are scored: 2500 held-out points of a 20k-point cloud let noise
// pick 1.1-1.3 times the best setting on a few evaluation cases, while four folds there cost
// what one costs at 80k points.
constexpr std::size_t kScoredPoints = 10000;
constexpr std::size_t kMaxFolds = 4;
constexpr std::size_t kMinPoints = 2000;
// The settings (setting_grid.hpp, pnf_eval_auto's grid).
constexpr const auto& kSigmaF = kGridSigmaF;
constexpr const auto& kSigmaG = kGridSigmaG;
constexpr const auto& kPasses = kGridPasses;
constexpr int kMaxPasses = kGridMaxPasses;
// The held-out points, drawn the same on every run of the same cloud.
constexpr unsigned kSeed = 14;

// The held-out points' neighbour lists (each point itself and the others, no other held-out
// point), and the arrays pnf_filter.h reads: held-out points first (rows [0, held)), then the
// others in their order.
struct Predictor {
  std::size_t held = 0;
  std::vector<pnf_real4> positions, normals;  // centred; the others' normals change with the passes
  std::vector<std::uint64_t> offsets;
  std::vector<std::uint32_t> indices;
};

void build_lists(Predictor& p, const SpatialIndex& index, double reach) {
  const std::vector<std::uint32_t> counts = index.count_within(reach, 0, p.held);
  const CsrLists all = index.lists_within(reach, 0, p.held, counts);
  p.offsets.assign(1, 0);
  p.indices.clear();
  for (std::size_t k = 0; k < p.held; ++k) {
    for (std::uint64_t e = all.offsets[k]; e < all.offsets[k + 1]; ++e) {
      if (all.indices[e] == k || all.indices[e] >= p.held) p.indices.push_back(all.indices[e]);
    }
    p.offsets.push_back(p.indices.size());
  }
}

// The held-out points' normals through the passes, each point seeing only its own normal and
// the others' (of the pass before); and for the first `nudged` of them (a random subset: the
// held-out points are in random order) the same from their input normal nudged along either
// direction of its tangent plane, for the divergence in Tally::score. The mean divergence varies
// little between points of one region (how much of its own normal a point keeps), so a few
// thousand points measure it, at a fraction of the cost of nudging them all.
struct HeldOutPasses {
  static constexpr double kNudge = 1e-5;  // radians; the reference is double
  std::vector<pnf_real4> input;
  std::vector<pnf_real4> out;        // from the input normals
  std::vector<Vec3> tangent[2];      // a basis of each nudged point's tangent plane
  std::vector<pnf_real4> nudged[2];  // from the input normal nudged along tangent[0], [1]

  HeldOutPasses(const std::vector<pnf_real4>& held_input, std::size_t nudged_points)
      : input(held_input), out(held_input) {
    const std::size_t m = std::min(nudged_points, input.size());
    for (int d = 0; d < 2; ++d) {
      tangent[d].resize(m);
      nudged[d].resize(m);
    }
    for (std::size_t k = 0; k < m; ++k) {
      const Vec3 own = {input[k].x, input[k].y, input[k].z};
      geometry::tangent_basis(own, tangent[0][k], tangent[1][k]);
      for (int d = 0; d < 2; ++d) {
        const Vec3& t = tangent[d][k];
        const Vec3 v = geometry::normalized({own[0] + kNudge * t[0], own[1] + kNudge * t[1], own[2] + kNudge * t[2]});
        nudged[d][k] = pnf_real4{v[0], v[1], v[2], 0};
      }
    }
  }

  // One pass over the others' current normals (p.normals from row p.held).
  void step(Predictor& p, const pnf_coeffs& c) {
    const auto held = static_cast<std::int64_t>(p.held);
#pragma omp parallel for schedule(dynamic, 64)
    for (std::int64_t k = 0; k < held; ++k) {
      // Row k is in no list but its own: each thread sets its own rows.
      auto advance = [&](pnf_real4& normal) {
        p.normals[k] = normal;
        int kept = 0;
        const pnf_vec3 v = pnf_filter_point(pnf_index(k), p.indices.data(), p.offsets[k], p.offsets[k + 1],
                                            p.positions.data(), p.normals.data(), c, &kept);
        normal = pnf_real4{v.x, v.y, v.z, 0};
      };
      advance(out[k]);
      if (std::size_t(k) < tangent[0].size()) {
        for (auto& n : nudged) advance(n[k]);
      }
    }
  }

  void add_to(Tally& tally) const {
    for (std::size_t k = 0; k < input.size(); ++k) {
      const double x = out[k].x - input[k].x, y = out[k].y - input[k].y, z = out[k].z - input[k].z;
      tally.distance2 += x * x + y * y + z * z;
    }
    for (std::size_t k = 0; k < tangent[0].size(); ++k) {
      for (int d = 0; d < 2; ++d) {
        const Vec3& t = tangent[d][k];
        const pnf_real4 &a = nudged[d][k], &b = out[k];
        tally.divergence += ((a.x - b.x) * t[0] + (a.y - b.y) * t[1] + (a.z - b.z) * t[2]) / kNudge;
      }
    }
    tally.points += double(input.size());
    tally.nudged += double(tangent[0].size());
  }
};

// The settings' tallies: index (sigma_f, sigma_g, passes) in the order of kSigmaF, kSigmaG, kPasses.
std::size_t setting_index(std::size_t f, std::size_t g, std::size_t pass) {
  return (f * std::size(kSigmaG) + g) * std::size(kPasses) + pass;
}

pnf_real4 unit4(const Vec3& v) {
  const double len = geometry::norm(v);
  return pnf_real4{v[0] / len, v[1] / len, v[2] / len, 0};
}

// The input normals' error, one sample per nudged held-out point: a linear normal field fitted
// to the tangent components of the input normals of the point and its nearest others (not other
// held-out points), the residual's mean square per component and degree of freedom. With
// independent errors of per-component variance v its mean is v whatever their distribution;
// on flat faces the field is exact, on curved ones it leaves second-order terms. The positions'
// own noise moves each point along the field while its normal stays the one of where it was: on
// a curved face that is a tilt of the field's gradient G times the displacement, of mean square
// position_noise^2 |G|^2 / 2 per component, which is not the input normals' error (the filter
// is judged against the true normals of the true points) and is taken off. Without that the
// torus at 0.5 spacings with 4-degree tilts measured more than its input's error, the bound took
// over and cross-validation kept too much of the input (4/off/1 mean radii, 1.11 of the best).
constexpr int kErrorNeighbours = 16;  // the point and 15 others
// The measured variance's margin in best_setting: its sampling error is under 1% (4000 samples
// of 26 degrees of freedom); the rest is for what the linear field leaves.
constexpr double kMeasuredErrorMargin = 0.05;
constexpr int kErrorCandidates = 24;  // nearest looked at, an eighth of them held out

double error_sample(const Predictor& p, const SpatialIndex& index, std::size_t k, double position_noise) {
  std::size_t ids[kErrorCandidates];
  double d2[kErrorCandidates];
  const std::size_t found = std::min<std::size_t>(kErrorCandidates, p.positions.size());
  index.nearest_of_point(k, found, ids, d2);
  std::vector<std::pair<double, std::size_t>> near;
  for (std::size_t e = 0; e < found; ++e) {
    if (ids[e] == k || ids[e] >= p.held) near.emplace_back(d2[e], ids[e]);
  }
  if (near.size() < std::size_t(kErrorNeighbours)) return NAN;
  std::sort(near.begin(), near.end());
  const Vec3 own = {p.normals[k].x, p.normals[k].y, p.normals[k].z};
  Vec3 t1, t2;
  geometry::tangent_basis(own, t1, t2);
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d bu = Eigen::Vector3d::Zero(), bv = Eigen::Vector3d::Zero();
  double uu = 0, vv = 0;
  for (int e = 0; e < kErrorNeighbours; ++e) {
    const std::size_t j = near[std::size_t(e)].second;
    const Vec3 d = {p.positions[j].x - p.positions[k].x, p.positions[j].y - p.positions[k].y,
                    p.positions[j].z - p.positions[k].z};
    Vec3 n = {p.normals[j].x, p.normals[j].y, p.normals[j].z};
    if (geometry::dot(n, own) < 0) n = {-n[0], -n[1], -n[2]};
    const Eigen::Vector3d row(1, geometry::dot(d, t1), geometry::dot(d, t2));
    const double u = geometry::dot(n, t1), v = geometry::dot(n, t2);
    a += row * row.transpose();
    bu += u * row;
    bv += v * row;
    uu += u * u;
    vv += v * v;
  }
  const Eigen::LDLT<Eigen::Matrix3d> solve(a);
  if (solve.info() != Eigen::Success || solve.rcond() < 1e-9) return NAN;
  const Eigen::Vector3d fit_u = solve.solve(bu), fit_v = solve.solve(bv);
  const double rss = uu - bu.dot(fit_u) + vv - bv.dot(fit_v);
  const double gradient2 = fit_u.tail<2>().squaredNorm() + fit_v.tail<2>().squaredNorm();
  const double moved = position_noise * position_noise * gradient2 / 2;
  return std::max(rss / (2.0 * (kErrorNeighbours - 3)) - moved, 0.0);
}

}  // namespace

double input_error_variance(const std::vector<double>& samples) {
  std::vector<double> sorted;
  for (double m : samples) {
    if (std::isfinite(m)) sorted.push_back(m);
  }
  if (sorted.empty()) return NAN;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted[sorted.size() / 2];
  // A fit across a crease mixes two faces' normals: tens of times the others. Cut at 4 medians,
  // which independent Gaussian errors pass with a chance of about 1e-10 (26 degrees of freedom).
  double sum = 0;
  std::size_t count = 0;
  for (double m : sorted) {
    if (m > 4 * median) break;
    sum += m;
    ++count;
  }
  return 2 * sum / double(count);  // two tangent components
}

// The setting's estimated error: with e a point's input error (independent, isotropic in the
// tangent plane, mean square s2) and out its normal after the passes, Stein's unbiased risk
// estimate gives the mean squared error of out as E|out - input|^2 - s2 (1 - div), div the mean
// divergence of out over the point's own input normal in its tangent plane (2 for passes that
// keep the input, 0 for passes that ignore it): the others' normals know nothing of e, so out
// depends on it only through the point's own normal. s2 from input_error_variance.
double Tally::estimated_error(double s2) const { return distance2 / points - s2 * (1 - divergence / nudged); }

std::size_t cross_validation_min_points() { return kMinPoints; }
std::size_t nudged_per_fold() { return kNudgedPoints; }
std::size_t rest_runs_per_fold() { return std::size(kSigmaF) * std::size(kSigmaG); }
double widest_reach_in_mean_radii() { return PNF_SUPPORT_IN_SIGMA_F * kSigmaF[std::size(kSigmaF) - 1]; }
std::vector<Tally> empty_tallies() {
  return std::vector<Tally>(std::size(kSigmaF) * std::size(kSigmaG) * std::size(kPasses));
}

HeldOutDraw draw_held_out(std::size_t n) {
  std::vector<std::uint32_t> ids(n);
  std::iota(ids.begin(), ids.end(), 0u);
  std::mt19937 rng(kSeed);
  std::shuffle(ids.begin(), ids.end(), rng);
  HeldOutDraw draw;
  draw.held = std::min(std::size_t(double(n) * kHeldOutShare), kMaxHeldOut);
  draw.folds = std::clamp<std::size_t>((kScoredPoints + draw.held - 1) / draw.held, 1, kMaxFolds);
  ids.resize(draw.held * draw.folds);
  draw.ids = std::move(ids);
  return draw;
}

void score_fold(const FoldRows& fold, double mean_radius, const RestRun& run_rest, const ProgressCallback& progress,
                std::vector<Tally>& tallies, std::vector<double>& error_samples, std::size_t& runs,
                std::size_t all_runs) {
  const std::size_t held = fold.held_positions.size(), rest = fold.rest_positions.size();
  Predictor p;
  p.held = held;
  std::vector<double> centred;
  centred.reserve(3 * (held + rest));
  auto add_row = [&](const Vec3& x, const Vec3& v) {
    for (int c = 0; c < 3; ++c) centred.push_back(x[c] - fold.centre[c]);
    p.positions.push_back(pnf_real4{x[0] - fold.centre[0], x[1] - fold.centre[1], x[2] - fold.centre[2], 0});
    p.normals.push_back(unit4(v));
  };
  for (std::size_t k = 0; k < held; ++k) add_row(fold.held_positions[k], fold.held_normals[k]);
  for (std::size_t k = 0; k < rest; ++k) add_row(fold.rest_positions[k], fold.rest_normals[k]);
  const std::vector<pnf_real4> held_input(p.normals.begin(), p.normals.begin() + std::ptrdiff_t(held));
  const std::vector<pnf_real4> rest_input(p.normals.begin() + std::ptrdiff_t(held), p.normals.end());
  const SpatialIndex index(std::move(centred), SpatialIndex::Layout::any_order);
  {
    const std::size_t first = error_samples.size();
    error_samples.resize(first + fold.nudged);
#pragma omp parallel for schedule(dynamic, 64)
    for (std::int64_t k = 0; k < std::int64_t(fold.nudged); ++k) {
      error_samples[first + std::size_t(k)] = error_sample(p, index, std::size_t(k), fold.position_noise);
    }
  }

  for (std::size_t f = 0; f < std::size(kSigmaF); ++f) {
    const double sigma_f = kSigmaF[f];
    build_lists(p, index, PNF_SUPPORT_IN_SIGMA_F * sigma_f * mean_radius);
    for (std::size_t g = 0; g < std::size(kSigmaG); ++g) {
      FilterParams params;
      params.sigma_f = sigma_f;
      params.sigma_g = kSigmaG[g];
      params.units = Units::radius;
      params.mean_radius = mean_radius;
      params.stop_change_deg = 0;
      params.iterations = kMaxPasses - 1;
      const pnf_coeffs c = pnf_make_coeffs(sigma_f * mean_radius, kSigmaG[g] * mean_radius);
      // Pass P at a held-out point: one step over the others' normals after P - 1 passes.
      HeldOutPasses passes(held_input, fold.nudged);
      std::copy(rest_input.begin(), rest_input.end(), p.normals.begin() + std::ptrdiff_t(held));
      auto step = [&](int pass) {
        passes.step(p, c);
        const auto* at = std::find(std::begin(kPasses), std::end(kPasses), pass);
        if (at != std::end(kPasses)) passes.add_to(tallies[setting_index(f, g, std::size_t(at - std::begin(kPasses)))]);
      };
      step(1);
      const double fraction = double(runs) / double(all_runs);
      auto still_wanted = [&](const PassProgress&) {
        return !progress || progress(PassProgress{0, 0, 0, ProgressStage::cross_validation, fraction});
      };
      run_rest(
          params,
          [&](int pass, const std::vector<double>& normals) {
            for (std::size_t k = 0; k < rest; ++k) {
              p.normals[held + k] = pnf_real4{normals[3 * k], normals[3 * k + 1], normals[3 * k + 2], 0};
            }
            step(pass + 1);
          },
          still_wanted);
      ++runs;
      if (progress &&
          !progress(PassProgress{0, 0, 0, ProgressStage::cross_validation, double(runs) / double(all_runs)})) {
        throw Error(ErrorCode::cancelled, "cross-validation cancelled");
      }
    }
  }
}

CrossValidation best_setting(const std::vector<Tally>& tallies, const HeldOutDraw& draw, double mean_radius,
                             double measured_input_error) {
  // The input's error s2 that the estimates subtract: every setting's error is >= 0, so s2 is at
  // most the least of E|out - input|^2 / (1 - div) over the settings with div < 1; subtracting
  // that bound picks the setting the bound came from (the generalised cross-validation of
  // smoothing splines), right where the best setting's error is small against the input's (the
  // bound is then tight) and biased towards the settings that keep less of each input where it
  // is not (jitter of 4 degrees on noisy positions: 4/2/1 mean radii on the wedges, 2.93 deg,
  // against 2.58 at 4/1/1). The measured variance (input_error_variance) is then lower; it
  // takes over with a margin for its own error, since where the bound is tight an s2 a few per
  // cent low would favour settings that keep the input (a plane with 12-degree tilts: 0.50 deg
  // against 0.19).
  double bound = HUGE_VAL;
  for (const Tally& t : tallies) {
    const double div = t.divergence / t.nudged;
    if (div < 1) bound = std::min(bound, t.distance2 / t.points / (1 - div));
  }
  const double input_error =
      std::isfinite(measured_input_error) ? std::min(bound, (1 + kMeasuredErrorMargin) * measured_input_error) : bound;
  CrossValidation best;
  best.input_error = input_error;
  best.measured_input_error = measured_input_error;
  best.held_out = draw.held * draw.folds;
  best.folds = draw.folds;
  best.settings = tallies.size();
  best.score = HUGE_VAL;
  for (std::size_t f = 0; f < std::size(kSigmaF); ++f) {
    for (std::size_t g = 0; g < std::size(kSigmaG); ++g) {
      for (std::size_t k = 0; k < std::size(kPasses); ++k) {
        const Tally& t = tallies[setting_index(f, g, k)];
        const double error = t.estimated_error(input_error);
        if (error < best.score) {
          best.score = error;
          best.divergence = t.divergence / t.nudged;
          best.params.sigma_f = kSigmaF[f];
          best.params.sigma_g = kSigmaG[g];
          best.params.iterations = kPasses[k];
        }
      }
    }
  }
  best.params.units = Units::radius;
  best.params.mean_radius = mean_radius;
  best.params.stop_change_deg = 0;
  return best;
}

CrossValidation cross_validate(const CloudView& cloud, double mean_radius, double position_noise, NormalFilter& filter,
                               const ProgressCallback& progress) {
  const std::size_t n = cloud.size();
  if (n < kMinPoints || cloud.normals.count != n) {
    throw Error(ErrorCode::invalid_argument, "cross-validation needs " + std::to_string(kMinPoints) +
                                                 " points or more, with normals; got " + std::to_string(n));
  }
  // As the filter checks them, before the folds renumber the points (the estimate that led here
  // skips bad normals; a NaN among the held-out ones would make every score NaN).
  check_cloud(cloud, CloudRequirements::filter());
  if (!(mean_radius > 0) || !std::isfinite(mean_radius)) {
    throw Error(ErrorCode::invalid_argument, "cross-validation needs a mean radius > 0");
  }
  if (!(position_noise >= 0) || !std::isfinite(position_noise)) {
    throw Error(ErrorCode::invalid_argument,
                "cross-validation needs a position noise >= 0 and finite, got " + std::to_string(position_noise));
  }
  const HeldOutDraw draw = draw_held_out(n);
  std::vector<bool> held_out(n);
  std::vector<Tally> tallies = empty_tallies();
  std::vector<double> error_samples;
  std::size_t runs = 0;
  const std::size_t all_runs = draw.folds * rest_runs_per_fold();
  for (std::size_t fold = 0; fold < draw.folds; ++fold) {
    FoldRows rows;
    rows.centre = bounding_box(cloud.positions).centre();
    rows.nudged = std::min(kNudgedPoints, draw.held);
    rows.position_noise = position_noise;
    std::fill(held_out.begin(), held_out.end(), false);
    for (std::size_t j = fold * draw.held; j < (fold + 1) * draw.held; ++j) {
      rows.held_positions.push_back(cloud.positions.at(draw.ids[j]));
      rows.held_normals.push_back(cloud.normals.at(draw.ids[j]));
      held_out[draw.ids[j]] = true;
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (held_out[i]) continue;
      rows.rest_positions.push_back(cloud.positions.at(i));
      rows.rest_normals.push_back(cloud.normals.at(i));
    }
    const CloudView rest(rows.rest_positions, rows.rest_normals);
    std::vector<Vec3> rest_out(rows.rest_positions.size());
    auto run_rest = [&](const FilterParams& params, const RestPassObserver& after_pass,
                        const ProgressCallback& still_wanted) {
      FilterFactory::run_observed(filter, rest, MutableVec3ArrayView(rest_out), params, after_pass, still_wanted);
    };
    score_fold(rows, mean_radius, run_rest, progress, tallies, error_samples, runs, all_runs);
  }
  return best_setting(tallies, draw, mean_radius, input_error_variance(error_samples));
}

}  // namespace pnf::detail
