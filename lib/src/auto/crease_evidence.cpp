#include "crease_evidence.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace pnf::detail {

CreaseEvidence crease_evidence(const CreaseFits& fits, double edge_residual, std::size_t points, double area_spacing) {
  CreaseEvidence e;
  e.samples = fits.residuals.size();
  std::vector<double> kinks;
  for (double r : fits.residuals) {
    if (!(r > edge_residual)) continue;
    ++e.edge_samples;
    kinks.push_back(std::sqrt(std::max(0.0, r * r - fits.noise * fits.noise)));
  }
  if (e.samples == 0 || !(fits.fit_radius > 0) || !(area_spacing > 0)) return e;
  if (!kinks.empty()) {
    std::nth_element(kinks.begin(), kinks.begin() + std::ptrdiff_t(kinks.size() / 2), kinks.end());
    e.sharpness = kinks[kinks.size() / 2] / fits.fit_radius;
  }
  const double share = double(e.edge_samples) / double(e.samples);
  const double area = double(points) * area_spacing * area_spacing;
  e.length_per_size = share * area / (2 * fits.fit_radius) / std::sqrt(area);
  return e;
}

}  // namespace pnf::detail
