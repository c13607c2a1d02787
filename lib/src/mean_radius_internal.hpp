// The mean-radius estimate and rule on an existing kd-tree, so that every caller builds only one.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "pnf/cloud_view.hpp"
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

// The origin that positions are re-centred on before the filter's kernels (float) and the
// estimates see them: per axis, the median of the points the spacing estimate samples (the
// curve ranks s * N / S, S = min(N, kMaxSpacingSamples)). Not the bounding-box centre: one point
// far from the rest (a stray return, a (0,0,0) row in georeferenced data) moved that centre so
// far from the others that their float positions lost the spacing (docs/method.md). `curve`:
// the positions' Morton order (morton_order). A distributed run takes the same samples and the
// same medians (mpi/mean_radius_mpi.cpp). N > 0.
Vec3 sample_median(const Vec3ArrayView& positions, const std::vector<std::uint32_t>& curve);
// x y z rows of `positions` less `centre`, in double (a far-away scan loses no digits): in the
// order `order` where given (the Morton curve: the filter's frame), else in the input's.
std::vector<double> centred_rows(const Vec3ArrayView& positions, const Vec3& centre,
                                 const std::vector<std::uint32_t>* order = nullptr);
// Per axis, the lower middle of `xyz` (x y z per point, at least one point): sample_median's
// medians, and a distributed run's over the samples it gathers.
Vec3 axis_medians(const std::vector<double>& xyz);

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
