// --auto's Stein risk estimate of filtered normals (stein_risk.hpp).
#include "stein_risk.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "geometry.hpp"
#include "spatial/spatial_order.hpp"

namespace pnf::detail {
namespace {

// A fixed pseudo-random sign per (sample, axis): the same probe on every run and every rank.
double sign_of(std::uint64_t key) {
  // splitmix64's finaliser.
  std::uint64_t z = key + 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  z ^= z >> 31;
  return (z & 1) ? 1.0 : -1.0;
}

}  // namespace

std::vector<std::size_t> stein_samples(const Vec3ArrayView& positions) {
  const std::vector<std::uint32_t> curve = morton_order(positions);
  const std::size_t n = curve.size(), m = std::min(n, kSteinMaxSamples);
  std::vector<std::size_t> samples(m);
  for (std::size_t s = 0; s < m; ++s) samples[s] = curve[s * n / m];
  return samples;
}

SteinRisk::SteinRisk(const std::vector<std::size_t>& samples, const std::vector<double>& unit_input, double noise_deg)
    : samples_(samples), noise_deg_(noise_deg) {
  input_ = at_samples(unit_input.data());
  probes_.resize(3 * samples_.size());
  for (std::size_t s = 0; s < samples_.size(); ++s) {
    const Vec3 n = {input_[3 * s], input_[3 * s + 1], input_[3 * s + 2]};
    const Vec3 b = {sign_of(3 * s), sign_of(3 * s + 1), sign_of(3 * s + 2)};
    // The errors lie in the tangent plane of the sphere; so does the probe.
    const double along = geometry::dot(b, n);
    for (int c = 0; c < 3; ++c) probes_[3 * s + std::size_t(c)] = b[std::size_t(c)] - along * n[std::size_t(c)];
  }
}

std::vector<double> SteinRisk::probed(const std::vector<double>& unit_input) const {
  std::vector<double> out = unit_input;
  for (std::size_t s = 0; s < samples_.size(); ++s) {
    for (int c = 0; c < 3; ++c)
      out[3 * samples_[s] + std::size_t(c)] += kSteinProbeStep * probes_[3 * s + std::size_t(c)];
  }
  return out;
}

std::vector<double> SteinRisk::at_samples(const double* normals) const {
  std::vector<double> rows(3 * samples_.size());
  for (std::size_t s = 0; s < samples_.size(); ++s) {
    const std::size_t row = samples_[s];
    const Vec3 n = geometry::normalized({normals[3 * row], normals[3 * row + 1], normals[3 * row + 2]});
    for (int c = 0; c < 3; ++c) rows[3 * s + std::size_t(c)] = n[std::size_t(c)];
  }
  return rows;
}

double SteinRisk::risk_deg(const std::vector<double>& filtered, const std::vector<double>& probed_filtered) const {
  if (empty()) return 0;
  double moved = 0, divergence = 0;
  for (std::size_t k = 0; k < filtered.size(); ++k) {
    moved += (filtered[k] - input_[k]) * (filtered[k] - input_[k]);
    divergence += probes_[k] * (probed_filtered[k] - filtered[k]) / kSteinProbeStep;
  }
  const double count = double(samples_.size());
  const double noise = noise_deg_ * geometry::kPi / 180;
  const double risk = moved / count - noise * noise + noise * noise * divergence / count;
  return std::copysign(std::sqrt(std::fabs(risk)), risk) * 180 / geometry::kPi;
}

}  // namespace pnf::detail
