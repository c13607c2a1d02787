#include "pnf/improve_normals.hpp"

#include "pnf/normal_filter.hpp"

namespace pnf {

FilterSummary improve_normals(const CloudView& cloud, MutableVec3ArrayView normals_out, const FilterParams& params,
                              const FilterOptions& options, const ProgressCallback& progress) {
  return NormalFilter(options).run(cloud, normals_out, params, progress);
}

FilterResult improve_normals(const PointCloud& cloud, const FilterParams& params, const FilterOptions& options) {
  return NormalFilter(options).run(cloud, params);
}

}  // namespace pnf
