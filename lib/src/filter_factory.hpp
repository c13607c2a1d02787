// Internal: what the library's own callers do with a NormalFilter beyond the public run():
// --auto's judged passes.
#pragma once

#include <functional>
#include <vector>

#include "pnf/normal_filter.hpp"

namespace pnf::detail {

struct FilterFactory {
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
