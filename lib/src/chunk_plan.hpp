// Splits a cloud into chunks of consecutive points whose neighbour lists fit a memory budget.
#pragma once

#include <cstdint>
#include <vector>

namespace pnf::detail {

struct Chunk {
  std::size_t first = 0;
  std::size_t count = 0;
};

// Bytes the CSR lists of `points` points with `pairs` neighbours in all take: 64-bit offsets
// (points + 1) and 32-bit indices.
std::size_t csr_bytes(std::size_t points, std::size_t pairs);

// Consecutive chunks covering all points, each as large as fits in `budget_bytes` (and in
// `max_buffer_bytes` for the index array alone). One chunk when the whole cloud fits. A point
// whose own list passes the budget gets a chunk of its own; one that passes max_buffer_bytes
// throws pnf::Error(invalid_argument) with the number of bytes it would need.
std::vector<Chunk> plan_chunks(const std::vector<std::uint32_t>& counts, std::size_t budget_bytes,
                               std::size_t max_buffer_bytes);

}  // namespace pnf::detail
