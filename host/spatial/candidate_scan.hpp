// The exact test of the neighbour lists, |p - s| <= radius, applied to one point's candidates (a
// search block's, see spatial_index.cpp): plain, auto-vectorised for AVX-512 and AVX2 through
// target_clones, and explicit AVX-512 / AVX2 scans chosen by CPU detection at run time. Every
// variant gives the same answer: the same double expression in the same order, no contraction.
#pragma once

#include <cstddef>
#include <cstdint>

#include "spatial/spatial_index.hpp"

namespace pnf::detail {

// A point's candidates as x, y, z arrays of `size` coordinates (re-centred, model units).
struct Candidates {
  const double* x;
  const double* y;
  const double* z;
  std::size_t size;
};

// How many candidates lie within sqrt(radius2) of (px, py, pz), by the scan `tuning` picks.
std::uint32_t count_candidates_within(const Candidates& c, double px, double py, double pz, double radius2,
                                      const SpatialIndex::ListTuning& tuning);

// Writes the ids (ids[k] for candidate k) of the candidates within into `out`, in candidate
// order, and returns how many. `out` must have room for 16 ids past the last one kept (the vector
// scans store full width).
std::size_t compact_candidates_within(const Candidates& c, const std::uint32_t* ids, double px, double py, double pz,
                                      double radius2, const SpatialIndex::ListTuning& tuning, std::uint32_t* out);

}  // namespace pnf::detail
