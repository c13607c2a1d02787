#include "pnf/estimate_normals.hpp"

// Only the two FLANN headers needed: the whole of flann/flann.hpp pulls in every index type.
#include <flann/algorithms/dist.h>
#include <flann/algorithms/kdtree_single_index.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "bounding_box.hpp"
#include "orient_normals.hpp"
#include "pnf/error.hpp"
#include "spatial_order.hpp"

namespace pnf {

namespace {

// Queries go to FLANN in blocks of this many points so that its size_t index and distance
// buffers (16 bytes per neighbour) stay at a few tens of MB for any N; each block is large
// enough to keep every thread busy.
constexpr std::size_t kQueryBlock = std::size_t{1} << 16;

// FLANN's default leaf size; the tree is built once and searched N times, so tuning it matters
// little next to the search itself.
constexpr int kLeafMaxSize = 10;

// The normal reported where the k + 1 fitted points coincide and no plane is defined. Any fixed
// unit vector would do; +z agrees with the mst seed rule.
constexpr Vec3 kDegenerateNormal = {0.0, 0.0, 1.0};

std::string format_vec3(const Vec3& v) {
  std::ostringstream text;
  text << '(' << v[0] << ", " << v[1] << ", " << v[2] << ')';
  return text.str();
}

void check_positions(const std::vector<Vec3>& positions) {
  if (positions.size() < 3) {
    throw Error(ErrorCode::invalid_input,
                "estimate_normals: need at least 3 points, got " + std::to_string(positions.size()));
  }
  if (positions.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    throw Error(ErrorCode::invalid_input,
                "estimate_normals: " + std::to_string(positions.size()) +
                    " points is more than the 2^31 - 1 that 32-bit neighbour ids can address");
  }
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const Vec3& p = positions[i];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      throw Error(ErrorCode::invalid_input,
                  "estimate_normals: vertex " + std::to_string(i) + " has a non-finite coordinate " + format_vec3(p));
    }
  }
}

using detail::bounding_box;

// The k nearest other points of every point, by an exact kd-tree search. Coordinates are taken
// relative to `centre` (the bounding-box centre) so that a translated cloud gives the same
// neighbours, up to rounding at the scale of the cloud rather than of its offset.
detail::NeighbourTable find_neighbours(const std::vector<Vec3>& positions, const Vec3& centre, int k) {
  const std::size_t count = positions.size();
  std::vector<double> centred(count * 3);
  for (std::size_t i = 0; i < count; ++i) {
    for (int axis = 0; axis < 3; ++axis) centred[i * 3 + axis] = positions[i][axis] - centre[axis];
  }

  const flann::Matrix<double> points(centred.data(), count, 3);
  flann::KDTreeSingleIndex<flann::L2<double>> index(points, flann::KDTreeSingleIndexParams(kLeafMaxSize));
  index.buildIndex();

  flann::SearchParams search;
  // Exact search; the single kd-tree is exact anyway, but say so rather than rely on it.
  search.checks = flann::FLANN_CHECKS_UNLIMITED;
  search.eps = 0.0f;
  search.sorted = true;
#ifdef _OPENMP
  // FLANN spreads the queries of one call over this many threads; each query's answer is
  // computed by one thread alone, so it does not depend on the count.
  search.cores = omp_get_max_threads();
#else
  search.cores = 1;
#endif

  // Each point's own entry is asked for too (k + 1 results) and then dropped.
  const auto wanted = static_cast<std::size_t>(k) + 1;
  detail::NeighbourTable table;
  table.point_count = count;
  table.k = k;
  table.indices.resize(count * static_cast<std::size_t>(k));
  std::vector<std::size_t> found(std::min(count, kQueryBlock) * wanted);
  // FLANN's L2 distances are SQUARED Euclidean distances; they are only needed for the sort
  // order, which FLANN has already applied, and are not read here.
  std::vector<double> squared_distances(found.size());

  for (std::size_t first = 0; first < count; first += kQueryBlock) {
    const std::size_t rows = std::min(kQueryBlock, count - first);
    const flann::Matrix<double> queries(centred.data() + first * 3, rows, 3);
    flann::Matrix<std::size_t> found_matrix(found.data(), rows, wanted);
    flann::Matrix<double> distance_matrix(squared_distances.data(), rows, wanted);
    index.knnSearch(queries, found_matrix, distance_matrix, wanted, search);

    for (std::size_t r = 0; r < rows; ++r) {
      const std::size_t point = first + r;
      // The point itself is normally the first result, but where duplicates sit at distance 0 it
      // may be further down or missing; then the farthest result is dropped instead.
      const std::size_t* results = found.data() + r * wanted;
      int* row = table.indices.data() + point * static_cast<std::size_t>(k);
      std::size_t filled = 0;
      for (std::size_t slot = 0; slot < wanted && filled < static_cast<std::size_t>(k); ++slot) {
        if (results[slot] != point) row[filled++] = static_cast<int>(results[slot]);
      }
    }
  }
  return table;
}

// The total-least-squares normal of point i and its neighbour row. Offsets are taken from p_i,
// not from the origin, so that far-from-origin clouds lose no digits; the covariance is summed
// about the centroid in a second pass for the same reason.
Vec3 fit_normal(const std::vector<Vec3>& positions, const detail::NeighbourTable& table, std::size_t point) {
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
  return Vec3{normal[0] / length, normal[1] / length, normal[2] / length};
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

std::vector<Vec3> estimate_normals(const std::vector<Vec3>& positions, const EstimateParams& params) {
  params.validate();
  check_positions(positions);

  const int k = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(params.k), positions.size() - 1));
  const detail::BoundingBox box = bounding_box(positions);
  // Curve order puts spatial neighbours near each other in memory: the kd-tree queries, PCA
  // gathers and mst traversal run several times faster than in a scan's row order.
  const std::vector<std::uint32_t> order = detail::morton_order(positions);
  std::vector<Vec3> sorted(positions.size());
  for (std::size_t s = 0; s < order.size(); ++s) sorted[s] = positions[order[s]];

  const detail::NeighbourTable neighbours = find_neighbours(sorted, box.centre(), k);
  std::vector<Vec3> sorted_normals(sorted.size());
  const auto count = static_cast<std::int64_t>(sorted.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t s = 0; s < count; ++s) {
    sorted_normals[static_cast<std::size_t>(s)] = fit_normal(sorted, neighbours, static_cast<std::size_t>(s));
  }

  switch (params.orientation) {
    case Orientation::viewpoint: detail::orient_towards_viewpoint(sorted, params.viewpoint, sorted_normals); break;
    case Orientation::outward: detail::orient_outward(sorted, sorted_normals); break;
    case Orientation::mst: detail::orient_by_mst(sorted, neighbours, sorted_normals); break;
  }

  std::vector<Vec3> normals(positions.size());
  for (std::size_t s = 0; s < order.size(); ++s) normals[order[s]] = sorted_normals[s];
  return normals;
}

}  // namespace pnf
