// The mean-radius estimate on an existing kd-tree, so the filter builds only one.
#pragma once

#include "neighbour_lists.hpp"

namespace pnf::detail {

// See pnf::estimate_mean_radius for the definition.
double estimate_mean_radius(const NeighbourSearch& search);

}  // namespace pnf::detail
