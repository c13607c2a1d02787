// pnf::improve_normals — the normal filter in one call: NormalFilter(options).run(...)
// (pnf/normal_filter.hpp, which says what a run does, what it costs and what it throws). Build a
// NormalFilter instead to filter several clouds: it compiles the OpenCL kernels once.
#pragma once

#include "pnf/cloud_view.hpp"
#include "pnf/filter_options.hpp"
#include "pnf/filter_params.hpp"
#include "pnf/filter_summary.hpp"
#include "pnf/point_cloud.hpp"
#include "pnf/progress.hpp"

namespace pnf {

// Writes the N improved unit normals of `cloud` into `normals_out` (N rows; it may be the cloud's
// own normals view).
FilterSummary improve_normals(const CloudView& cloud, MutableVec3ArrayView normals_out, const FilterParams& params = {},
                              const FilterOptions& options = {}, const ProgressCallback& progress = {});
// The same on a PointCloud, returning the normals.
FilterResult improve_normals(const PointCloud& cloud, const FilterParams& params = {},
                             const FilterOptions& options = {});

}  // namespace pnf
