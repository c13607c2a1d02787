#include "chunk_plan.hpp"

#include <gtest/gtest.h>

#include "pnf/error.hpp"

namespace {

using pnf::detail::csr_bytes;
using pnf::detail::plan_chunks;

TEST(ChunkPlan, OneChunkWhenEverythingFits) {
  std::vector<std::uint32_t> counts(100, 10);
  auto chunks = plan_chunks(counts, csr_bytes(100, 1000), 1 << 20);
  ASSERT_EQ(chunks.size(), 1u);
  EXPECT_EQ(chunks[0].first, 0u);
  EXPECT_EQ(chunks[0].count, 100u);
}

TEST(ChunkPlan, ChunksCoverAllPointsAndRespectTheBudget) {
  std::vector<std::uint32_t> counts;
  for (int i = 0; i < 1000; ++i) counts.push_back(1 + (i * 37) % 50);
  const std::size_t budget = 2000;
  auto chunks = plan_chunks(counts, budget, 1 << 20);
  ASSERT_GT(chunks.size(), 1u);
  std::size_t next = 0;
  for (const auto& c : chunks) {
    EXPECT_EQ(c.first, next);
    std::size_t pairs = 0;
    for (std::size_t i = c.first; i < c.first + c.count; ++i) pairs += counts[i];
    EXPECT_LE(csr_bytes(c.count, pairs), budget);
    next += c.count;
  }
  EXPECT_EQ(next, counts.size());
}

TEST(ChunkPlan, APointLargerThanTheBudgetGetsItsOwnChunk) {
  std::vector<std::uint32_t> counts = {1, 1000, 1};
  auto chunks = plan_chunks(counts, 64, 1 << 20);
  ASSERT_EQ(chunks.size(), 3u);
  EXPECT_EQ(chunks[1].first, 1u);
  EXPECT_EQ(chunks[1].count, 1u);
}

TEST(ChunkPlan, AListLargerThanTheDeviceBufferIsAnErrorWithTheNumbers) {
  std::vector<std::uint32_t> counts = {1, 1000, 1};
  try {
    plan_chunks(counts, 1 << 20, 100);
    FAIL() << "no error";
  } catch (const pnf::Error& e) {
    EXPECT_EQ(e.code(), pnf::ErrorCode::invalid_argument);
    EXPECT_NE(std::string(e.what()).find("point 1 has 1000 entries (4000 bytes)"), std::string::npos) << e.what();
  }
}

}  // namespace
