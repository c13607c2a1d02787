// The interface both backends implement: the engine (filter_engine.cpp) does the ordering,
// neighbour search and chunking; a backend holds the cloud and runs passes over CSR lists.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "device_memory_error.hpp"
#include "pnf/normal_filter.hpp"
#include "pnf_filter.h"

namespace pnf::detail {

// Where a backend's caller writes the lists of one chunk (begin_lists).
struct ListStorage {
  std::uint64_t* offsets = nullptr;  // count + 1
  std::uint32_t* indices = nullptr;  // pairs
};

// Thread safety: one backend serves one run at a time. A backend throws DeviceMemoryError
// (device_memory_error.hpp) when the device refuses an allocation; the engine then retries with
// smaller chunks.
class FilterBackend {
 public:
  virtual ~FilterBackend() = default;
  virtual std::string description() const = 0;
  // Largest neighbour index array (bytes) one chunk may have.
  virtual std::size_t max_list_bytes() const = 0;
  // positions and normals: N by 3, row-major, re-centred, in curve order, unit normals. The
  // lists loaded before stay (a twin run's passes and the cloud's share them).
  virtual void upload_cloud(const std::vector<double>& positions, const std::vector<double>& normals) = 0;
  // Blocks until the device has finished all work queued so far.
  virtual void wait() = 0;
  // Storage for the CSR lists of points [first, first + count), `pairs` indices in all, that the
  // caller fills before end_lists(). On OpenCL it is the mapped device buffer, so the lists are
  // written once, straight where the kernel reads them (no host copy on CPU devices).
  virtual ListStorage begin_lists(std::size_t first, std::size_t count, std::size_t pairs) = 0;
  // The filled lists become the ones run_chunk uses.
  virtual void end_lists() = 0;
  // New normals for points [first, first + count) of the current lists (0 is the lists' first
  // point), from the current normals, with the run's coefficients (FilterPlan::coefficients).
  // Queued: wait() tells when they are done. The engine runs a chunk in slices so that it can
  // report progress and honour a cancel within a pass.
  virtual void run_chunk(const pnf_coeffs& coefficients, std::size_t first, std::size_t count) = 0;
  // Makes the new normals current (Jacobi). Returns the device seconds of the pass's kernels,
  // or 0 when not measured.
  virtual double end_pass() = 0;
  // Points of the pass end_pass() last closed whose J was degenerate, so their normal was kept
  // (docs/method.md, the normal update). A backend that does not count returns 0.
  virtual std::size_t degenerate_kept() const { return 0; }
  // Bytes of device memory this backend holds (0 for the host reference).
  virtual std::size_t device_bytes() const = 0;
  // The current normals, N by 3.
  virtual std::vector<double> download_normals() = 0;
  // Replaces the current normals (N by 3, unit), between passes: a distributed run's halo.
  virtual void replace_normals(const std::vector<double>& normals) = 0;
};

// The backend `options` ask for; options.device must be resolved (Device::resolved). lanes: the
// OpenCL kernel's neighbours per vector step (1, 4, 8 or 16; 0: the device type's default),
// ignored by the reference. Throws pnf::Error(device) when the OpenCL device cannot be set up.
std::unique_ptr<FilterBackend> make_backend(const FilterOptions& options, int lanes = 0);

}  // namespace pnf::detail
