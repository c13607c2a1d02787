// Internal to --auto: the samples of one scale and their neighbourhoods, shared by the estimate's
// fits (estimate_data.cpp) and the judge (surface_judge.hpp), which look at the same samples at
// the same scales: a scale searched once serves both.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace pnf::detail {

class SpatialIndex;

// At most this many neighbour look-ups per scale (samples x neighbours): bounds the cost on any N
// while leaving hundreds of samples for the medians even at the largest scale.
constexpr std::size_t kMaxLookupsPerScale = 1000000;
// Never more samples than this at any scale: a median of 4000 is good to about 2%.
constexpr std::size_t kMaxSamples = 4000;

struct SampleNeighbourhoods {
  int neighbours = 0;               // per sample, the sample itself included
  std::vector<std::size_t> selves;  // the samples' points
  // samples x neighbours: each sample's nearest points, nearest first, equal distances in curve
  // order (sort_neighbours), and their squared distances (model units^2).
  std::vector<std::size_t> ids;
  std::vector<double> squared_distances;

  std::size_t samples() const { return selves.size(); }
  const std::size_t* ids_of(std::size_t s) const { return &ids[s * std::size_t(neighbours)]; }
  const double* squared_distances_of(std::size_t s) const { return &squared_distances[s * std::size_t(neighbours)]; }
};

// How many samples a scale of `neighbours` points takes on a cloud of `points`.
std::size_t samples_at_scale(std::size_t points, int neighbours);

// `samples` samples (at most N), spread evenly along `curve` (the points' morton_order; sample s
// is point curve[floor(s N / samples)]), each with its `neighbours` nearest points, so that
// nothing depends on the input's row order (`rank`: ranks_of(curve)). In parallel; `poll` is
// asked on the calling thread about every 0.1 s with the share done, and false from it stops the
// search and throws pnf::Error(cancelled) naming `caller`. Needs 1 <= neighbours <= N.
SampleNeighbourhoods sample_neighbourhoods(const SpatialIndex& index, const std::vector<std::uint32_t>& curve,
                                           const std::vector<std::uint32_t>& rank, std::size_t samples, int neighbours,
                                           const std::function<bool(double fraction)>& poll, const char* caller);

}  // namespace pnf::detail
