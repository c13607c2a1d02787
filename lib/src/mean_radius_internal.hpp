// The mean-radius estimate and rule on an existing kd-tree, so that every caller builds only one.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "pnf/mean_radius.hpp"
#include "spatial/spatial_index.hpp"

namespace pnf::detail {

// pnf::estimate_mean_radius on `index`. curve_order: null when the index's points are in Morton
// order (the filter's, estimate's); else the Morton order of the index's points (morton_order of
// them), so that the same points are sampled and the estimate is the same bit for bit.
double estimate_mean_radius(const SpatialIndex& index, const std::vector<std::uint32_t>* curve_order = nullptr);

// pnf::mean_radius's rule with the estimate computed by `estimate` (called only when needed) for
// a cloud of `points` points with `radii` (empty: none).
MeanRadius resolve_mean_radius(double given, const ScalarArrayView& radii, std::size_t points,
                               const std::function<double()>& estimate);

}  // namespace pnf::detail
