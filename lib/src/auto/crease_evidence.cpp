#include "crease_evidence.hpp"

#include <cmath>

namespace pnf::detail {

CreaseEvidence crease_evidence(const CreaseFits& fits, double edge_residual, std::size_t points, double area_spacing) {
  CreaseEvidence e;
  e.samples = fits.residuals.size();
  for (double r : fits.residuals) e.edge_samples += r > edge_residual;
  if (e.samples == 0 || !(fits.fit_radius > 0) || !(area_spacing > 0)) return e;
  const double share = double(e.edge_samples) / double(e.samples);
  const double area = double(points) * area_spacing * area_spacing;
  e.length_per_size = share * area / (2 * fits.fit_radius) / std::sqrt(area);
  return e;
}

}  // namespace pnf::detail
