// --auto's held-out check (held_out_planes.hpp).
#include "held_out_planes.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "geometry.hpp"
#include "mean_radius_internal.hpp"
#include "spatial/spatial_index.hpp"
#include "spatial/spatial_order.hpp"

namespace pnf::detail {
namespace {

// The half a point lies in: the samples' half (true) or the reference planes' (false).
bool in_sample_half(const Vec3& p) { return (position_hash(p) & 1) != 0; }

// How far to look for the reference's points among the whole cloud's nearest: each lies in the
// other half with probability 1/2, so 4 times as many hold them all but about once in 10^4.
constexpr std::size_t kSearchedPerPlanePoint = 4;

}  // namespace

HeldOutPlanes::HeldOutPlanes(const Vec3ArrayView& positions, const std::vector<double>& unit_input) {
  const std::size_t n = positions.count;
  const std::vector<std::uint32_t> curve = morton_order(positions);
  std::vector<char> sample_half(n);
  std::vector<std::size_t> candidates;  // the sample half, in curve order
  for (std::size_t i = 0; i < n; ++i) sample_half[i] = in_sample_half(positions.at(i));
  for (std::uint32_t i : curve) {
    if (sample_half[i]) candidates.push_back(i);
  }
  const std::size_t m = std::min(candidates.size(), kHeldOutMaxSamples);
  if (m == 0 || n - candidates.size() < std::size_t(kHeldOutPlanePoints)) return;
  std::vector<std::size_t> rows(m);
  for (std::size_t s = 0; s < m; ++s) rows[s] = candidates[s * candidates.size() / m];

  const SpatialIndex index(centred_rows(positions, sample_median(positions, curve)), SpatialIndex::Layout::any_order);
  const std::vector<double>& xyz = index.positions();
  const std::size_t searched = std::min(n, kSearchedPerPlanePoint * kHeldOutPlanePoints + 1);
  std::vector<double> planes(3 * m);
  std::vector<char> fitted(m, 0);
#pragma omp parallel
  {
    std::vector<std::size_t> ids(searched);
    std::vector<double> squared(searched);
#pragma omp for schedule(dynamic, 64)
    for (long long si = 0; si < static_cast<long long>(m); ++si) {
      const std::size_t s = std::size_t(si);
      index.nearest_of_point(rows[s], searched, ids.data(), squared.data());
      Eigen::Matrix<double, 3, kHeldOutPlanePoints> points;
      Eigen::Vector3d oriented = Eigen::Vector3d::Zero();
      int count = 0;
      for (std::size_t j = 0; j < searched && count < kHeldOutPlanePoints; ++j) {
        const std::size_t id = ids[j];
        if (sample_half[id]) continue;
        points.col(count++) = Eigen::Vector3d(xyz[3 * id], xyz[3 * id + 1], xyz[3 * id + 2]);
        oriented += Eigen::Vector3d(unit_input[3 * id], unit_input[3 * id + 1], unit_input[3 * id + 2]);
      }
      if (count < kHeldOutPlanePoints) continue;
      const Eigen::Matrix<double, 3, kHeldOutPlanePoints> spread = points.colwise() - points.rowwise().mean();
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(spread * spread.transpose());
      // Points on one line or at one place (a scanner's repeated returns) make no plane, as in
      // the estimate's fits (sample_fit.cpp): no reference there.
      if (!(solver.eigenvalues()(1) > 0)) continue;
      Eigen::Vector3d plane = solver.eigenvectors().col(0);
      if (plane.dot(oriented) < 0) plane = -plane;
      for (int k = 0; k < 3; ++k) planes[3 * s + std::size_t(k)] = plane[k];
      fitted[s] = 1;
    }
  }
  for (std::size_t s = 0; s < m; ++s) {
    if (!fitted[s]) continue;
    samples_.push_back(rows[s]);
    planes_.insert(planes_.end(), planes.begin() + std::ptrdiff_t(3 * s), planes.begin() + std::ptrdiff_t(3 * s + 3));
    // Made unit as score makes the normals it scores, so that the input gains exactly nothing.
    const std::size_t row = rows[s];
    const Vec3 input = geometry::normalized({unit_input[3 * row], unit_input[3 * row + 1], unit_input[3 * row + 2]});
    input_.insert(input_.end(), input.begin(), input.end());
  }
}

HeldOutPlanes::Score HeldOutPlanes::score(const double* normals) const {
  Score score;
  if (samples_.empty()) return score;
  double disagreement = 0, gain = 0, gain_squared = 0;
  for (std::size_t s = 0; s < samples_.size(); ++s) {
    const std::size_t row = samples_[s];
    const Vec3 n = geometry::normalized({normals[3 * row], normals[3 * row + 1], normals[3 * row + 2]});
    const Vec3 plane = {planes_[3 * s], planes_[3 * s + 1], planes_[3 * s + 2]};
    const Vec3 input = {input_[3 * s], input_[3 * s + 1], input_[3 * s + 2]};
    const double along = geometry::dot(n, plane);
    const double g = along - geometry::dot(input, plane);
    disagreement += 1 - along;
    gain += g;
    gain_squared += g * g;
  }
  const double count = double(samples_.size());
  const double mean = gain / count;
  const double variance = std::max(gain_squared / count - mean * mean, 0.0);
  score.disagreement_deg = std::acos(std::clamp(1 - disagreement / count, -1.0, 1.0)) * 180 / geometry::kPi;
  score.gain_z = variance > 0 ? mean / std::sqrt(variance / count) : 0;
  return score;
}

}  // namespace pnf::detail
