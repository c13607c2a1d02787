#include "spatial/spatial_order.hpp"

#include <algorithm>
#include <cstring>
#include <numeric>
#include <vector>

#include "pnf/bounding_box.hpp"

namespace pnf::detail {
namespace {

constexpr int kBitsPerAxis = 21;  // 3 x 21 = 63 bits: the whole key fits one uint64
constexpr double kCellsPerAxis = double((1u << kBitsPerAxis) - 1);

// Spreads the low 21 bits of v so that there are two zero bits between each.
std::uint64_t spread_bits(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

}  // namespace

MortonFrame morton_frame(const Vec3& low, const Vec3& high) {
  double extent = 0;
  for (int k = 0; k < 3; ++k) extent = std::max(extent, high[k] - low[k]);
  return {low, extent > 0 ? kCellsPerAxis / extent : 0};
}

std::uint64_t morton_key(const MortonFrame& frame, const Vec3& p) {
  std::uint64_t key = 0;
  for (int k = 0; k < 3; ++k) {
    auto cell = static_cast<std::uint64_t>((p[k] - frame.low[k]) * frame.to_cells);
    key |= spread_bits(cell) << k;
  }
  return key;
}

bool canonical_before(const Vec3& a, const Vec3& b) {
  for (int k = 0; k < 3; ++k) {
    std::uint64_t bits_a = 0, bits_b = 0;
    std::memcpy(&bits_a, &a[k], sizeof bits_a);
    std::memcpy(&bits_b, &b[k], sizeof bits_b);
    if (bits_a != bits_b) return bits_a < bits_b;
  }
  return false;
}

std::vector<std::uint32_t> morton_order(const Vec3ArrayView& positions, const Vec3ArrayView* normals,
                                        const MortonFrame* given) {
  const std::size_t n = positions.count;
  const BoundingBox box = bounding_box(positions);
  const MortonFrame frame = given ? *given : morton_frame(box.min, box.max);
  std::vector<std::uint64_t> keys(n);
  for (std::size_t i = 0; i < n; ++i) keys[i] = morton_key(frame, positions.at(i));
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    if (keys[a] != keys[b]) return keys[a] < keys[b];
    const Vec3 pa = positions.at(a), pb = positions.at(b);
    if (canonical_before(pa, pb)) return true;
    if (canonical_before(pb, pa) || normals == nullptr) return false;
    return canonical_before(normals->at(a), normals->at(b));
  });
  return order;
}

std::vector<std::uint32_t> ranks_of(const std::vector<std::uint32_t>& order) {
  std::vector<std::uint32_t> rank(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) rank[order[k]] = std::uint32_t(k);
  return rank;
}

void sort_neighbours(std::size_t* ids, double* squared_distances, std::size_t k,
                     const std::vector<std::uint32_t>& rank) {
  struct Neighbour {
    double squared_distance;
    std::uint32_t rank;
    std::size_t id;
  };
  std::vector<Neighbour> keyed(k);
  for (std::size_t j = 0; j < k; ++j) keyed[j] = {squared_distances[j], rank[ids[j]], ids[j]};
  std::sort(keyed.begin(), keyed.end(), [](const Neighbour& a, const Neighbour& b) {
    return a.squared_distance != b.squared_distance ? a.squared_distance < b.squared_distance : a.rank < b.rank;
  });
  for (std::size_t j = 0; j < k; ++j) {
    squared_distances[j] = keyed[j].squared_distance;
    ids[j] = keyed[j].id;
  }
}

}  // namespace pnf::detail
