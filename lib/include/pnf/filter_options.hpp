// pnf::FilterOptions — how and where the filter runs (device, memory, limits): what a
// NormalFilter is built with (pnf/normal_filter.hpp) and improve_normals takes.
#pragma once

#include <cstddef>

#include "pnf/device.hpp"

namespace pnf {

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

}  // namespace pnf
