// The interface both backends implement: the engine (normal_filter.cpp) does the ordering,
// neighbour search and chunking; a backend holds the cloud and runs passes over CSR lists.
#pragma once

#include <cstdint>
#include <string>

#include <vector>
#include "device_memory_error.hpp"

namespace pnf::detail {

// Exponent coefficients in model units^-2, as pnf_make_coeffs computes them (pnf_filter.h).
struct Coefficients {
  double inv_two_sigma_f2 = 0;
  double inv_two_sigma_g2 = 0;
};

// Thrown by a backend when the device refuses an allocation (out of device memory or
// resources); the engine then retries with smaller chunks.

struct ListStorage {
  std::uint64_t* offsets = nullptr;  // count + 1
  std::uint32_t* indices = nullptr;  // pairs
};

class FilterBackend {
 public:
  virtual ~FilterBackend() = default;
  virtual std::string description() const = 0;
  // Largest neighbour index array (bytes) one chunk may have.
  virtual std::size_t max_list_bytes() const = 0;
  // positions and normals: N by 3, row-major, re-centred, in curve order, unit normals.
  virtual void upload_cloud(const std::vector<double>& positions, const std::vector<double>& normals) = 0;
  // Blocks until the device has finished all work queued so far.
  virtual void wait() = 0;
  // Storage for the CSR lists of points [first, first + count), `pairs` indices in all, that the
  // caller fills before end_lists(). On OpenCL it is the mapped device buffer, so the lists are
  // written once, straight where the kernel reads them (no host copy on CPU devices).
  virtual ListStorage begin_lists(std::size_t first, std::size_t count, std::size_t pairs) = 0;
  // The filled lists become the ones run_chunk uses.
  virtual void end_lists() = 0;
  // New normals for the points of the current lists, from the current normals.
  virtual void run_chunk(const Coefficients& coefficients) = 0;
  // Makes the new normals current (Jacobi). Returns the device seconds of the pass's kernels,
  // or 0 when not measured.
  virtual double end_pass() = 0;
  // Points of the pass end_pass() last closed whose J was degenerate, so their normal was kept
  // (SPEC, "The normal update"). A backend that does not count returns 0.
  virtual std::size_t degenerate_kept() const { return 0; }
  // Bytes of device memory this backend holds (0 for the host reference).
  virtual std::size_t device_bytes() const = 0;
  // The current normals, N by 3.
  virtual std::vector<double> download_normals() = 0;
  // Replaces the current normals (N by 3, unit), between passes: a distributed run's halo.
  virtual void replace_normals(const std::vector<double>& normals) = 0;
};

}  // namespace pnf::detail
