#include "filter_plan.hpp"

namespace pnf::detail {

FilterPlan make_filter_plan(const FilterParams& params, const MeanRadius& radius) {
  FilterPlan plan;
  double scale = 1.0;  // model units per parameter unit
  if (params.units == Units::radius) {
    plan.radius = radius;
    scale = radius.value;
  }
  plan.sigma_f = params.sigma_f * scale;
  plan.sigma_g = params.sigma_g * scale;
  plan.reach = PNF_SUPPORT_IN_SIGMA_F * plan.sigma_f;
  plan.coefficients = pnf_make_coeffs(plan.sigma_f, plan.sigma_g);
  return plan;
}

}  // namespace pnf::detail
