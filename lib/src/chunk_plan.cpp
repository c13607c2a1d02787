#include "chunk_plan.hpp"

#include <string>

#include "pnf/error.hpp"

namespace pnf::detail {

std::size_t csr_bytes(std::size_t points, std::size_t pairs) {
  return (points + 1) * sizeof(std::uint64_t) + pairs * sizeof(std::uint32_t);
}

std::vector<Chunk> plan_chunks(const std::vector<std::uint32_t>& counts, std::size_t budget_bytes,
                               std::size_t max_buffer_bytes) {
  std::vector<Chunk> chunks;
  Chunk current;
  std::size_t pairs = 0;
  for (std::size_t i = 0; i < counts.size(); ++i) {
    std::size_t own = std::size_t(counts[i]) * sizeof(std::uint32_t);
    if (own > max_buffer_bytes) {
      throw Error(ErrorCode::invalid_argument, "the neighbour list of point " + std::to_string(i) + " has " +
                                                   std::to_string(counts[i]) + " entries (" + std::to_string(own) +
                                                   " bytes), more than the device's largest buffer (" +
                                                   std::to_string(max_buffer_bytes) + " bytes); lower sigma_f");
    }
    std::size_t grown = pairs + counts[i];
    bool fits =
        csr_bytes(current.count + 1, grown) <= budget_bytes && grown * sizeof(std::uint32_t) <= max_buffer_bytes;
    if (!fits && current.count > 0) {
      chunks.push_back(current);
      current = Chunk{i, 0};
      pairs = 0;
      grown = counts[i];
    }
    current.count += 1;
    pairs = grown;
  }
  if (current.count > 0) chunks.push_back(current);
  return chunks;
}

}  // namespace pnf::detail
