// What one run's FilterParams mean for its cloud: the sigmas in model units, the reach of the
// neighbour lists and the kernel's coefficients. Made once per run, from the parameters and the
// mean radius, by everything that turns parameters into work: the engine (filter_engine.cpp), a
// distributed run's ranks (mpi/improve_normals.cpp, whose halo is the reach) and the benches.
#pragma once

#include "pnf/filter_params.hpp"
#include "pnf/mean_radius.hpp"
#include "pnf_filter.h"

namespace pnf::detail {

struct FilterPlan {
  // The mean surfel radius the sigmas are multiples of (Units::radius); {0, not_used} with
  // Units::absolute.
  MeanRadius radius;
  double sigma_f = 0;  // model units
  double sigma_g = 0;  // model units
  // PNF_SUPPORT_IN_SIGMA_F (2) sigma_f, model units: a neighbour list holds every point within
  // this distance of its point, inclusive (docs/method.md).
  double reach = 0;
  // The exponent coefficients 1 / (2 sigma^2), model units^-2, in double (pnf_make_coeffs, the
  // reference's scalar); a float device rounds each once when it sets its kernel's arguments.
  pnf_coeffs coefficients{};
};

// params must be valid (FilterParams::validate). radius: with Units::radius the resolved mean
// radius (value > 0); ignored with Units::absolute. Pure function.
FilterPlan make_filter_plan(const FilterParams& params, const MeanRadius& radius);

}  // namespace pnf::detail
