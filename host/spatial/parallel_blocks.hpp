// The cancellable scheduler of SpatialIndex's long searches: blocks of work on every OpenMP
// thread while the calling thread asks a WorkPoll (spatial_index.hpp) how far it may go.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <exception>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "pnf/error.hpp"
#include "spatial/spatial_index.hpp"

namespace pnf::detail {

// How often the calling thread asks a WorkPoll: often enough for a progress bar and a prompt
// cancel, rarely enough that a Python callback (which takes the GIL) costs nothing measurable.
inline constexpr double kPollSeconds = 0.2;

// Runs work(b) for b in [0, blocks) on all OpenMP threads, one block per grab (dynamic), while
// the master thread (the calling thread) asks `poll` before its first block and then every
// kPollSeconds between its own blocks.
// A false answer, or an exception from poll, makes every thread stop at its next grab; then this
// throws Error(cancelled), or rethrows the exception. `work` must not throw.
template <typename Setup, typename Work>
void parallel_blocks(std::size_t blocks, const WorkPoll& poll, Setup&& setup, Work&& work) {
  std::atomic<std::size_t> next{0}, done{0};
  std::atomic<bool> stop{false};
  std::exception_ptr failure;
  std::chrono::steady_clock::time_point
      last_poll{};  // long ago: the first grab asks, so even a short search can be cancelled
#pragma omp parallel
  {
    auto state = setup();
#ifdef _OPENMP
    const bool polls = poll && omp_get_thread_num() == 0;
#else
    const bool polls = bool(poll);
#endif
    for (;;) {
      if (polls &&
          std::chrono::duration<double>(std::chrono::steady_clock::now() - last_poll).count() >= kPollSeconds) {
        try {
          if (!poll(double(done.load(std::memory_order_relaxed)) / double(blocks))) stop = true;
        } catch (...) {
          failure = std::current_exception();
          stop = true;
        }
        last_poll = std::chrono::steady_clock::now();
      }
      if (stop.load(std::memory_order_relaxed)) break;
      const std::size_t b = next.fetch_add(1, std::memory_order_relaxed);
      if (b >= blocks) break;
      work(state, b);
      done.fetch_add(1, std::memory_order_relaxed);
    }
  }
  if (failure) std::rethrow_exception(failure);
  if (stop) throw Error(ErrorCode::cancelled, "cancelled while searching neighbours");
}

}  // namespace pnf::detail
