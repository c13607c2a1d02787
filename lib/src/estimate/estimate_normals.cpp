#include "pnf/estimate_normals.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>

#include "cloud_checks.hpp"
#include "mean_radius_internal.hpp"
#include "orient_normals.hpp"
#include "pnf/bounding_box.hpp"
#include "pnf/error.hpp"
#include "spatial/spatial_index.hpp"
#include "spatial/spatial_order.hpp"

namespace pnf {

namespace {

// The normal reported where the k fitted points coincide and no plane is defined. Any fixed
// unit vector would do; +z agrees with the mst seed rule.
constexpr Vec3 kDegenerateNormal = {0.0, 0.0, 1.0};

std::string format_vec3(const Vec3& v) {
  std::ostringstream text;
  text << '(' << v[0] << ", " << v[1] << ", " << v[2] << ')';
  return text.str();
}

// estimate_normals' requirements: a plane needs 3 points, and the neighbour table holds int ids.
detail::CloudRequirements estimate_requirements() {
  detail::CloudRequirements requirements;
  requirements.caller = "estimate_normals";
  requirements.min_points = 3;
  requirements.checks_normals = false;
  requirements.max_points = static_cast<std::size_t>(std::numeric_limits<int>::max());
  return requirements;
}

// The total-least-squares normal of point i and its neighbour row (its table.k nearest other
// points, so table.k + 1 = EstimateParams::k points in all). Offsets are taken from p_i,
// not from the origin, so that far-from-origin clouds lose no digits; the covariance is summed
// about the centroid in a second pass for the same reason.
// When `curvature` is given, it receives the fit's surface variation lambda0 / (lambda0 + lambda1
// + lambda2) (0 for a degenerate fit, as PCL gives it).
Vec3 fit_normal(const std::vector<Vec3>& positions, const detail::NeighbourTable& table, std::size_t point,
                double* curvature) {
  if (curvature) *curvature = 0.0;
  const Eigen::Vector3d origin(positions[point][0], positions[point][1], positions[point][2]);
  const int* row = table.row(point);
  const int fitted = table.k + 1;
  const auto offset = [&](int slot) -> Eigen::Vector3d {
    if (slot == table.k) return Eigen::Vector3d::Zero();  // the point itself
    const Vec3& q = positions[static_cast<std::size_t>(row[slot])];
    return Eigen::Vector3d(q[0], q[1], q[2]) - origin;
  };

  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int slot = 0; slot < fitted; ++slot) centroid += offset(slot);
  centroid /= static_cast<double>(fitted);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (int slot = 0; slot < fitted; ++slot) {
    const Eigen::Vector3d d = offset(slot) - centroid;
    covariance.noalias() += d * d.transpose();
  }
  // An exact zero is the only input the solver cannot give a plane for: it rescales internally,
  // so even a tiny spread still yields a valid eigenvector.
  if (covariance.trace() == 0.0) return kDegenerateNormal;

  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  // Eigenvalues come in increasing order, so column 0 spans the direction of least spread.
  const Eigen::Vector3d normal = solver.eigenvectors().col(0);
  const double length = normal.norm();
  if (solver.info() != Eigen::Success || !std::isfinite(length) || length == 0.0) {
    return kDegenerateNormal;
  }
  if (curvature) {
    // The eigenvalues sum to the trace (> 0 here); the smallest may round to a tiny negative.
    const Eigen::Vector3d lambda = solver.eigenvalues();
    *curvature = std::abs(lambda[0]) / (lambda[0] + lambda[1] + lambda[2]);
  }
  return Vec3{normal[0] / length, normal[1] / length, normal[2] / length};
}

// Points fitted between two progress reports' time checks: a few milliseconds of work at k = 16.
constexpr std::size_t kFitBlock = std::size_t{1} << 14;

using Clock = std::chrono::steady_clock;

// Reports stage `stage` at `fraction`, with the seconds since `start`; throws
// Error(cancelled) when the callback answers false.
void report(const ProgressCallback& progress, ProgressStage stage, Clock::time_point start, double fraction) {
  if (!progress) return;
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (!progress(PassProgress{0, 0, seconds, stage, fraction})) {
    throw Error(ErrorCode::cancelled,
                std::string("estimate_normals cancelled during the ") + to_string(stage) + " stage");
  }
}

}  // namespace

const char* to_string(Orientation orientation) {
  switch (orientation) {
    case Orientation::viewpoint: return "viewpoint";
    case Orientation::outward: return "outward";
    case Orientation::mst: return "mst";
  }
  return "unknown";
}

Orientation parse_orientation(const std::string& name) {
  for (const Orientation candidate : {Orientation::viewpoint, Orientation::outward, Orientation::mst}) {
    if (name == to_string(candidate)) return candidate;
  }
  throw Error(ErrorCode::invalid_argument, "orientation '" + name + "' is not one of viewpoint, outward, mst");
}

void EstimateParams::validate() const {
  if (k < 3) {
    throw Error(ErrorCode::invalid_argument,
                "EstimateParams.k = " + std::to_string(k) + " is out of range; need k >= 3");
  }
  if (orientation != Orientation::viewpoint && orientation != Orientation::outward && orientation != Orientation::mst) {
    throw Error(ErrorCode::invalid_argument,
                "EstimateParams.orientation = " + std::to_string(static_cast<int>(orientation)) +
                    " is not a valid Orientation");
  }
  if (!std::isfinite(viewpoint[0]) || !std::isfinite(viewpoint[1]) || !std::isfinite(viewpoint[2])) {
    throw Error(ErrorCode::invalid_argument, "EstimateParams.viewpoint = " + format_vec3(viewpoint) + " is not finite");
  }
}

namespace {

// estimate_normals, with the surface variations into `curvature_out` (N values) when it is given.
void estimate(const Vec3ArrayView& positions, MutableVec3ArrayView normals_out, double* curvature_out,
              const EstimateParams& params, const ProgressCallback& progress) {
  params.validate();
  detail::check_cloud(CloudView(positions), estimate_requirements());
  if (normals_out.count != positions.count || (positions.count > 0 && normals_out.data == nullptr)) {
    throw Error(ErrorCode::invalid_argument, "estimate_normals: the output view has " +
                                                 std::to_string(normals_out.count) + " rows for " +
                                                 std::to_string(positions.count) + " points");
  }
  const std::size_t n = positions.count;
  // The k nearest points include the point itself (PCL's and Open3D's count): k − 1 others.
  const int others = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(params.k) - 1, n - 1));
  const Vec3 centre = bounding_box(positions).centre();
  // Curve order puts spatial neighbours near each other in memory: the kd-tree queries, PCA
  // gathers and mst traversal run several times faster than in a scan's row order.
  const std::vector<std::uint32_t> order = detail::morton_order(positions);
  std::vector<Vec3> sorted(n);
  for (std::size_t s = 0; s < n; ++s) sorted[s] = positions.at(order[s]);
  // The k − 1 nearest other points of every point, by an exact kd-tree search. Coordinates are
  // taken relative to the bounding-box centre so that a translated cloud gives the same neighbours, up
  // to rounding at the scale of the cloud rather than of its offset.
  std::vector<double> centred = detail::centred_rows(positions, centre, &order);
  auto stage_start = Clock::now();
  detail::WorkPoll poll;
  if (progress) {
    poll = [&](double fraction) {
      report(progress, ProgressStage::lists, stage_start, fraction);
      return true;
    };
  }
  const detail::NeighbourTable neighbours = detail::SpatialIndex(std::move(centred)).nearest_table(others, poll);
  report(progress, ProgressStage::lists, stage_start, 1.0);

  // The fits, a block of points at a time so that the calling thread can report between blocks.
  // The orientation that follows gets the last kOrientShare of the stage.
  constexpr double kOrientShare = 0.5;
  stage_start = Clock::now();
  auto last_report = stage_start;
  std::vector<Vec3> sorted_normals(n);
  std::vector<double> sorted_curvature(curvature_out ? n : 0);
  for (std::size_t block = 0; block < n; block += kFitBlock) {
    const auto stop = static_cast<std::int64_t>(std::min(n, block + kFitBlock));
#pragma omp parallel for schedule(static)
    for (std::int64_t s = static_cast<std::int64_t>(block); s < stop; ++s) {
      const auto point = static_cast<std::size_t>(s);
      sorted_normals[point] = fit_normal(sorted, neighbours, point, curvature_out ? &sorted_curvature[point] : nullptr);
    }
    if (progress && std::chrono::duration<double>(Clock::now() - last_report).count() >= 0.2) {
      report(progress, ProgressStage::estimate, stage_start, (1 - kOrientShare) * double(stop) / double(n));
      last_report = Clock::now();
    }
  }
  report(progress, ProgressStage::estimate, stage_start, 1 - kOrientShare);

  switch (params.orientation) {
    case Orientation::viewpoint: detail::orient_towards_viewpoint(sorted, params.viewpoint, sorted_normals); break;
    case Orientation::outward: detail::orient_outward(sorted, sorted_normals); break;
    case Orientation::mst: detail::orient_by_mst(sorted, neighbours, sorted_normals); break;
  }
  report(progress, ProgressStage::estimate, stage_start, 1.0);
  for (std::size_t s = 0; s < n; ++s) normals_out.set(order[s], sorted_normals[s]);
  if (curvature_out) {
    for (std::size_t s = 0; s < n; ++s) curvature_out[order[s]] = sorted_curvature[s];
  }
}

}  // namespace

void estimate_normals(const Vec3ArrayView& positions, MutableVec3ArrayView normals_out, const EstimateParams& params,
                      const ProgressCallback& progress) {
  estimate(positions, normals_out, nullptr, params, progress);
}

std::vector<Vec3> estimate_normals(const std::vector<Vec3>& positions, const EstimateParams& params,
                                   const ProgressCallback& progress) {
  std::vector<Vec3> normals(positions.size());
  estimate_normals(Vec3ArrayView(positions), MutableVec3ArrayView(normals), params, progress);
  return normals;
}

std::vector<Vec3> estimate_normals(const std::vector<Vec3>& positions, std::vector<double>& curvature_out,
                                   const EstimateParams& params, const ProgressCallback& progress) {
  std::vector<Vec3> normals(positions.size());
  std::vector<double> curvature(positions.size());
  estimate(Vec3ArrayView(positions), MutableVec3ArrayView(normals), curvature.data(), params, progress);
  curvature_out.swap(curvature);
  return normals;
}

}  // namespace pnf
