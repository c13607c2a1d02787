// The mean-radius estimate and rule on an existing kd-tree, so that every caller builds only one.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "pnf/mean_radius.hpp"
#include "spatial/spatial_index.hpp"

namespace pnf::detail {

// The estimate (docs/method.md, "The mean radius"): the median, over up to kMaxSpacingSamples
// points spread evenly along the curve, of each one's mean distance to its kSpacingNeighbours
// nearest other points. A distributed run (mpi/mean_radius_mpi.cpp) takes the same samples and
// distances on the same index type, so that its estimate is this one bit for bit.
// The 4 nearest points of a square-grid sample are its edge neighbours at exactly the spacing.
constexpr int kSpacingNeighbours = 4;
// Enough samples for a median to a fraction of a percent; bounds the cost on huge clouds.
constexpr std::size_t kMaxSpacingSamples = 100000;

// The median of the samples' mean distances, those at 0 left out (a point whose nearest are all
// duplicates of it says nothing about the spacing); 0 when none is left.
double median_spacing(std::vector<double> distances);

// Throws pnf::Error(invalid_input): the mean radius of `points` points cannot be estimated.
[[noreturn]] void throw_cannot_estimate_mean_radius(std::size_t points);

// pnf::estimate_mean_radius on `index`. curve_order: null when the index's points are in Morton
// order (the filter's, estimate's); else the Morton order of the index's points (morton_order of
// them), so that the same points are sampled and the estimate is the same bit for bit.
double estimate_mean_radius(const SpatialIndex& index, const std::vector<std::uint32_t>* curve_order = nullptr);

// pnf::mean_radius's rule with the estimate computed by `estimate` (called only when needed) for
// a cloud of `points` points with `radii` (empty: none).
MeanRadius resolve_mean_radius(double given, const ScalarArrayView& radii, std::size_t points,
                               const std::function<double()>& estimate);

}  // namespace pnf::detail
