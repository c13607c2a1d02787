// Internal: NormalFilters with kernel tuning that the public options leave to the device type.
// The bench and the parity tests use it to time and check every lane width.
#pragma once

#include <functional>
#include <vector>

#include "pnf/normal_filter.hpp"

namespace pnf::detail {

struct FilterFactory {
  // A filter whose OpenCL kernel takes `lanes` neighbours per vector step (1, 4, 8 or 16; 0: the
  // device type's default, as NormalFilter(options) picks). Ignored by the reference backend.
  static NormalFilter with_lanes(const FilterOptions& options, int lanes);
  // filter.run(cloud, normals_out, params, progress), telling `after_pass` the new normals (N by
  // 3, the view's order) after every pass: --auto's judge scores the passes in between without
  // running the first ones again. params.mean_radius must be given with
  // Units::radius. When `enough` is given and returns true after a pass's observer, the passes end
  // there (as the stop rule ends them).
  using PassObserver = std::function<void(int pass, const std::vector<double>& normals)>;
  static FilterSummary run_observed(NormalFilter& filter, const CloudView& cloud, MutableVec3ArrayView normals_out,
                                    const FilterParams& params, const PassObserver& after_pass,
                                    const ProgressCallback& progress = {}, const std::function<bool()>& enough = {});
};

}  // namespace pnf::detail
