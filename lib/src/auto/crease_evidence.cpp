#include "crease_evidence.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace pnf::detail {

double crease_length_per_size(double share, double fit_radius, std::size_t points, double area_spacing) {
  if (!(fit_radius > 0) || !(area_spacing > 0)) return 0;
  const double area = double(points) * area_spacing * area_spacing;
  return share * area / (2 * fit_radius) / std::sqrt(area);
}

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
  e.length_per_size =
      crease_length_per_size(double(e.edge_samples) / double(e.samples), fits.fit_radius, points, area_spacing);
  return e;
}

}  // namespace pnf::detail
