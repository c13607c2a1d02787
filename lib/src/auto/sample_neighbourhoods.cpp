// --auto's samples and their neighbourhoods at one scale (sample_neighbourhoods.hpp).
#include "sample_neighbourhoods.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <string>

#include "pnf/error.hpp"
#include "spatial/spatial_index.hpp"
#include "spatial/spatial_order.hpp"

namespace pnf::detail {

std::size_t samples_at_scale(std::size_t points, int neighbours) {
  return std::min({points, kMaxSamples, std::max<std::size_t>(1, kMaxLookupsPerScale / std::size_t(neighbours))});
}

SampleNeighbourhoods sample_neighbourhoods(const SpatialIndex& index, const std::vector<std::uint32_t>& curve,
                                           const std::vector<std::uint32_t>& rank, std::size_t samples, int neighbours,
                                           const std::function<bool(double fraction)>& poll, const char* caller) {
  const std::size_t count = index.size(), k = std::size_t(neighbours);
  samples = std::min(samples, count);
  SampleNeighbourhoods n;
  n.neighbours = neighbours;
  n.selves.resize(samples);
  n.ids.resize(samples * k);
  n.squared_distances.resize(samples * k);
  auto cancelled = [&] {
    return Error(ErrorCode::cancelled, std::string(caller) + ": cancelled while searching the samples' neighbours");
  };
  // Asked once before the workers start: the master may find every sample taken.
  if (poll && !poll(0)) throw cancelled();
  std::atomic<bool> stop{false};
  std::atomic<std::size_t> done{0};
  std::chrono::steady_clock::time_point last_poll = std::chrono::steady_clock::now();
#pragma omp parallel for schedule(dynamic, 16)
  for (long long s = 0; s < static_cast<long long>(samples); ++s) {
    if (stop.load(std::memory_order_relaxed)) continue;
    const std::size_t self = curve[std::size_t(s) * count / samples];
    n.selves[std::size_t(s)] = self;
    std::size_t* ids = &n.ids[std::size_t(s) * k];
    double* distances = &n.squared_distances[std::size_t(s) * k];
    index.nearest_of_point(self, k, ids, distances);
    sort_neighbours(ids, distances, k, rank);
    const std::size_t finished = done.fetch_add(1, std::memory_order_relaxed) + 1;
    if (poll && omp_get_thread_num() == 0 &&
        std::chrono::steady_clock::now() - last_poll > std::chrono::milliseconds(100)) {
      last_poll = std::chrono::steady_clock::now();
      if (!poll(double(finished) / double(samples))) stop = true;
    }
  }
  if (stop) throw cancelled();
  return n;
}

}  // namespace pnf::detail
