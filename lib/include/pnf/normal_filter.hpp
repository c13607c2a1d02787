// pnf::NormalFilter — the normal filter of Jones, Durand and Zwicker (2004) on an OpenCL device
// or on the CPU reference.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "pnf/cloud_view.hpp"
#include "pnf/filter_options.hpp"
#include "pnf/filter_params.hpp"
#include "pnf/filter_summary.hpp"
#include "pnf/point_cloud.hpp"
#include "pnf/progress.hpp"

namespace pnf {

// FilterOptions: pnf/filter_options.hpp; FilterSummary and FilterResult: pnf/filter_summary.hpp;
// PassProgress, ProgressStage and ProgressCallback: pnf/progress.hpp; the one-shot call
// improve_normals: pnf/improve_normals.hpp.

// A filter bound to one backend and device. The OpenCL program is compiled once, at
// construction; each run() builds the cloud's neighbour lists once and reuses them and the
// device buffers across all passes. Not thread safe: use one NormalFilter per thread.
class NormalFilter {
 public:
  // Throws pnf::Error: invalid_argument from options.validate(); device when the OpenCL backend
  // finds no matching device (listing the devices it found) or the kernels fail to build (with
  // the build log).
  explicit NormalFilter(const FilterOptions& options = {});
  ~NormalFilter();
  NormalFilter(NormalFilter&&) noexcept;
  NormalFilter& operator=(NormalFilter&&) noexcept;

  // Improves the normals of `cloud` (N positions and N oriented normals, optional N radii; float
  // or double, any stride, read in place) as docs/method.md defines: `params.iterations` Jacobi passes of
  // n' = C n / |C n|, C = adj(dF/dx)^T, never flipping a normal to the other side, and writes the
  // N new unit normals into `normals_out` (N rows; it may be the cloud's own normals view: the
  // input normals are read before anything is written). Positions are not changed. Non-unit
  // normals are normalised first. Host memory beyond the caller's arrays: one re-centred double
  // copy of the positions and two of the normals (the kd-tree's and the passes'), the float
  // copies the device needs, and the neighbour lists (see docs/performance.md).
  // Throws pnf::Error: invalid_argument for bad params or a normals_out of the wrong size;
  // invalid_input for a cloud without normals, with mismatched sizes, a NaN or infinite
  // coordinate, a zero normal or a bad radius (naming the first offending vertex), or a mean
  // radius that cannot be estimated; cancelled when `progress` returns false (normals_out is then
  // unchanged). An empty cloud gives an empty result.
  FilterSummary run(const CloudView& cloud, MutableVec3ArrayView normals_out, const FilterParams& params = {},
                    const ProgressCallback& progress = {});
  // The same on a PointCloud, returning the normals.
  FilterResult run(const PointCloud& cloud, const FilterParams& params = {}, const ProgressCallback& progress = {});

  // run(cloud, normals_out, params, progress), telling `observe` the new normals after every pass
  // (N by 3 doubles in the cloud's row order, unit to rounding; valid during the call), for a
  // caller that scores the passes as they go (as --auto's judge does) without running the first
  // ones again. When `observe` returns false the passes end there, as the stop rule ends them:
  // normals_out gets that pass's normals and the summary says how many passes ran.
  using PassObserver = std::function<bool(int pass, const std::vector<double>& normals)>;
  FilterSummary run_observed(const CloudView& cloud, MutableVec3ArrayView normals_out, const FilterParams& params,
                             const PassObserver& observe, const ProgressCallback& progress = {});

  // run_observed, beside the same passes from other normals on the same positions
  // (`twin_normals`, N rows, such as the input nudged to probe the filter) over the same
  // neighbour lists, built once as they depend on the positions only: `observe_twin` sees the
  // twin's passes (and may end them) and its normals are then dropped. Each twin pass runs just
  // before the cloud's pass of that number, so the twin runs no pass past the cloud's last where
  // the lists stay whole on the device; where they are filled chunk by chunk, the twin's passes
  // all run first. The summary is the cloud's run; its list and upload times count both. Throws
  // as run does, for the twin's normals too.
  FilterSummary run_observed_after_twin(const CloudView& cloud, const Vec3ArrayView& twin_normals,
                                        const PassObserver& observe_twin, MutableVec3ArrayView normals_out,
                                        const FilterParams& params, const PassObserver& observe,
                                        const ProgressCallback& progress = {});

  // The device in use, or "CPU reference (double)" for the reference backend.
  std::string device_description() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pnf
