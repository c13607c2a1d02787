// pnf::NormalFilter — the normal filter of Jones, Durand and Zwicker (2004) on an OpenCL device
// or on the CPU reference.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "pnf/cloud_view.hpp"
#include "pnf/device.hpp"
#include "pnf/filter_params.hpp"
#include "pnf/point_cloud.hpp"
#include "pnf/progress.hpp"

namespace pnf {

namespace detail {
struct FilterFactory;  // internal: builds filters with kernel tuning the public options do not expose
}

// How much memory and work a run may take.
struct MemoryPolicy {
  // Neighbour lists (4 bytes a pair, plus 8 a point) larger than this are not kept for the whole
  // cloud: the cloud is processed in chunks of points whose lists fit, rebuilt each pass (all but
  // the chunk that ended the previous pass, whose lists are still in the buffer). Same
  // result, bounded memory. The lists are written once, into the device buffer (on a CPU device
  // that is host memory). Default 3 GiB: the paper's 400k-point dog (1.3 GB of lists) stays
  // whole, a 2M-point cloud at sigma_f 8 (6.5 GB) runs in chunks under 4 GiB in all. > 0.
  std::size_t budget_bytes = std::size_t(3) << 30;
  // A run whose neighbour lists would pass this many pairs is refused before they are counted
  // or built, with the estimate in the message: at 2^36 (default) the lists alone take 256 GiB,
  // and a pass takes minutes even on a GPU. Typical scans have 50 to 1000 neighbours a point. > 0.
  std::size_t max_neighbour_pairs = std::size_t(1) << 36;

  // Throws pnf::Error(invalid_argument) naming the first bad field and its value.
  void validate() const;
};

// How and where the filter runs; fixed for the life of a NormalFilter.
struct FilterOptions {
  // Default: the PNF_DEVICE variable, else OpenCL by the default rule (see Device).
  Device device;
  MemoryPolicy memory;
  // Threads for the reference backend; 0 (default) means all cores. >= 0.
  int reference_threads = 0;
  // A run estimated to take longer than this many seconds (lists and passes, from the pair
  // estimate and a probe that times this device on a few million pairs) is refused before the
  // lists are built, with the numbers. Runs under max_seconds * 1e7 pair evaluations are not
  // probed (no device is slower; at the default that is a few times the 2M-point sigma_f 8 run). 0: no
  // limit. >= 0, finite. Default 10 minutes: fifty times the paper's 400k-point dog setting on
  // PoCL with 2 cores, while a neighbourhood spanning a large cloud (hours) is refused in a second.
  double max_seconds = 600;

  // Throws pnf::Error(invalid_argument) naming the first bad field and its value.
  void validate() const;
};

// Where the mean surfel radius came from.
enum class RadiusSource { not_used, given, property, estimate };
const char* to_string(RadiusSource source);

// What a run did, for the caller to report (the library never prints).
struct FilterSummary {
  std::size_t points = 0;
  double mean_radius = 0;  // model units; 0 with Units::absolute
  RadiusSource radius_source = RadiusSource::not_used;
  double sigma_f = 0;  // model units
  double sigma_g = 0;  // model units
  double neighbours_mean = 0;
  std::size_t neighbours_max = 0;
  std::size_t neighbour_pairs = 0;  // sum of list lengths, per pass
  std::size_t chunks = 0;           // 1 when the lists fit the memory budget
  std::size_t device_bytes = 0;     // device buffers held (0 for the reference backend)
  int allocation_retries = 0;       // times the device refused a buffer and chunks were halved
  std::string backend;
  std::string device;                   // the device, with platform and driver
  double neighbour_seconds = 0;         // counting and building the lists (all passes if chunked)
  double upload_seconds = 0;            // positions, normals and lists to the device
  std::vector<double> pass_seconds;     // wall time of each pass
  std::vector<double> kernel_seconds;   // device time of each pass (OpenCL event profiling)
  int passes_run = 0;                   // < iterations when the stop rule ended the run early
  std::size_t degenerate_kept = 0;      // normals kept because J was degenerate (docs/method.md), summed over passes
  std::vector<double> mean_change_deg;  // per pass, with the stop rule: mean angle to the previous pass
};

// The PointCloud conveniences' result.
struct FilterResult {
  std::vector<Vec3> normals;  // N unit normals, in input order
  FilterSummary summary;
};

// PassProgress, ProgressStage and ProgressCallback: pnf/progress.hpp.


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

  // The device in use, or "CPU reference (double)" for the reference backend.
  std::string device_description() const;

 private:
  friend struct detail::FilterFactory;
  struct Impl;
  explicit NormalFilter(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// One-shot conveniences: NormalFilter(options).run(...).
FilterSummary improve_normals(const CloudView& cloud, MutableVec3ArrayView normals_out, const FilterParams& params = {},
                              const FilterOptions& options = {}, const ProgressCallback& progress = {});
FilterResult improve_normals(const PointCloud& cloud, const FilterParams& params = {},
                             const FilterOptions& options = {});

}  // namespace pnf
