#include "spatial/spatial_order.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numeric>
#include <utility>
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

// The sample's share of the points beyond the bulk at each end, per axis: up to this many stray
// points leave the bulk's box as it is.
constexpr double kBulkQuantile = 0.001;
// The bulk's box is widened by this share of its width on each side: a surface's own extreme
// points, beyond the quantiles, mostly stay inside.
constexpr double kBulkMargin = 0.125;
// sort_neighbours sorts this many neighbours and more by radix (12 byte passes at most), fewer
// with std::sort: at k = 257-4097 the comparison sort was 40-50% of the estimate's searches.
constexpr std::size_t kRadixSortFrom = 128;
// About this many points make the sample (all of them in smaller clouds).
constexpr std::uint64_t kCurveSamplePoints = std::uint64_t{1} << 16;

double box_extent(const Vec3& low, const Vec3& high) {
  double extent = 0;
  for (int k = 0; k < 3; ++k) extent = std::max(extent, high[k] - low[k]);
  return extent;
}

// SplitMix64's finaliser: every bit of the coordinates moves every bit of the hash.
std::uint64_t mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace

std::uint64_t curve_sample_stride(std::uint64_t points) {
  return std::max<std::uint64_t>(1, points / kCurveSamplePoints);
}

std::uint64_t position_hash(const Vec3& p) {
  std::uint64_t hash = 0;
  for (int k = 0; k < 3; ++k) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &p[k], sizeof bits);
    hash = mix(hash ^ bits);
  }
  return hash;
}

std::vector<double> curve_sample(const Vec3ArrayView& positions, std::uint64_t stride) {
  std::vector<double> sample;
  for (std::size_t i = 0; i < positions.count; ++i) {
    const Vec3 p = positions.at(i);
    if (position_hash(p) % stride == 0) sample.insert(sample.end(), p.begin(), p.end());
  }
  return sample;
}

double axis_order_statistic(const std::vector<double>& xyz, int axis, std::size_t index) {
  std::vector<double> values(xyz.size() / 3);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = xyz[3 * i + std::size_t(axis)];
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(index), values.end());
  return values[index];
}

MortonFrame morton_frame(const Vec3& low, const Vec3& high, const std::vector<double>& sample_xyz) {
  const double extent = box_extent(low, high);
  const MortonFrame whole = {low, extent > 0 ? kCellsPerAxis / extent : 0};
  const std::size_t m = sample_xyz.size() / 3;
  if (m == 0) return whole;
  const auto lower = std::size_t(std::floor(kBulkQuantile * double(m - 1)));
  const auto upper = std::size_t(std::ceil((1 - kBulkQuantile) * double(m - 1)));
  Vec3 bulk_low, bulk_high;
  for (int k = 0; k < 3; ++k) {
    bulk_low[std::size_t(k)] = axis_order_statistic(sample_xyz, k, lower);
    bulk_high[std::size_t(k)] = axis_order_statistic(sample_xyz, k, upper);
  }
  const double bulk = box_extent(bulk_low, bulk_high);
  if (!(bulk > 0) || !(extent > kFarBoxPerBulk * bulk)) return whole;
  Vec3 corner;
  for (int k = 0; k < 3; ++k) corner[k] = bulk_low[k] - kBulkMargin * bulk;
  return {corner, kCellsPerAxis / ((1 + 2 * kBulkMargin) * bulk)};
}

MortonFrame morton_frame_of(const Vec3ArrayView& positions) {
  const BoundingBox box = bounding_box(positions);
  return morton_frame(box.min, box.max, curve_sample(positions, curve_sample_stride(positions.count)));
}

std::uint64_t morton_key(const MortonFrame& frame, const Vec3& p) {
  std::uint64_t key = 0;
  for (int k = 0; k < 3; ++k) {
    const double cell = std::clamp((p[k] - frame.low[k]) * frame.to_cells, 0.0, kCellsPerAxis);
    key |= spread_bits(static_cast<std::uint64_t>(cell)) << k;
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
  const MortonFrame frame = given ? *given : morton_frame_of(positions);
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
  // Squared distances are >= +0, whose bits order as their values: the key is (bits, rank).
  struct Neighbour {
    std::uint64_t distance_bits;
    std::uint32_t rank;
    std::size_t id;
  };
  thread_local std::vector<Neighbour> keyed, spare;  // called once per sample, in parallel
  keyed.resize(k);
  for (std::size_t j = 0; j < k; ++j) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &squared_distances[j], sizeof bits);
    keyed[j] = {bits, rank[ids[j]], ids[j]};
  }
  if (k < kRadixSortFrom) {
    std::sort(keyed.begin(), keyed.end(), [](const Neighbour& a, const Neighbour& b) {
      return a.distance_bits != b.distance_bits ? a.distance_bits < b.distance_bits : a.rank < b.rank;
    });
  } else {
    // Least significant digit first, each pass stable: the rank's 4 bytes, then the distance's 8;
    // a byte all keys share is skipped.
    auto digit = [](const Neighbour& n, int d) -> unsigned {
      return unsigned(d < 4 ? n.rank >> (8 * d) : n.distance_bits >> (8 * (d - 4))) & 255u;
    };
    std::array<std::array<std::size_t, 256>, 12> counts{};
    for (const Neighbour& n : keyed) {
      for (int d = 0; d < 12; ++d) ++counts[std::size_t(d)][digit(n, d)];
    }
    spare.resize(k);
    for (int d = 0; d < 12; ++d) {
      std::array<std::size_t, 256>& count = counts[std::size_t(d)];
      if (count[digit(keyed[0], d)] == k) continue;
      std::size_t start = 0;
      for (std::size_t& c : count) start += std::exchange(c, start);
      for (const Neighbour& n : keyed) spare[count[digit(n, d)]++] = n;
      keyed.swap(spare);
    }
  }
  for (std::size_t j = 0; j < k; ++j) {
    std::memcpy(&squared_distances[j], &keyed[j].distance_bits, sizeof(double));
    ids[j] = keyed[j].id;
  }
}

}  // namespace pnf::detail
