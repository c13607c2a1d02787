#include "spatial/candidate_scan.hpp"

#include "wide_clones.hpp"

#if defined(__GNUC__) && defined(__x86_64__)
#include <immintrin.h>
#endif

namespace pnf::detail {
namespace {

// The neighbourhood |p - s| <= radius, inclusive (docs/method.md, "Reach"), decided here and only here (in the scans
// below, which all inline it). The library is compiled without floating-point contraction
// (-ffp-contract=off, lib/CMakeLists.txt: GCC fused these products into FMAs in the AVX-512 scans
// before), so every build and every instruction set below rounds this expression the same way and
// gives the same lists (test SpatialIndex.EveryScanVariantRoundsTheDistanceUnfused).
inline bool within(double dx, double dy, double dz, double radius2) { return dx * dx + dy * dy + dz * dz <= radius2; }

// How many of a point's candidates are within. Written once, built twice: plain (the build's
// baseline, SSE2 on x86-64) and, through target_clones, for AVX-512 and AVX2 too, picked at load
// time by the CPU (the loop is vectorised across candidates).
inline std::uint32_t count_scan_body(const Candidates& c, double px, double py, double pz, double radius2) {
  std::uint32_t n = 0;
  for (std::size_t k = 0; k < c.size; ++k) n += within(c.x[k] - px, c.y[k] - py, c.z[k] - pz, radius2);
  return n;
}

PNF_WIDE_CLONES std::uint32_t count_scan_wide(const Candidates& c, double px, double py, double pz, double radius2) {
  return count_scan_body(c, px, py, pz, radius2);
}
std::uint32_t count_scan_plain(const Candidates& c, double px, double py, double pz, double radius2) {
  return count_scan_body(c, px, py, pz, radius2);
}
// The scalar ends of the vector scans below: candidates [k, size) by within() itself.
inline std::uint32_t count_tail(const Candidates& c, std::size_t k, double px, double py, double pz, double radius2) {
  std::uint32_t n = 0;
  for (; k < c.size; ++k) n += within(c.x[k] - px, c.y[k] - py, c.z[k] - pz, radius2);
  return n;
}
inline std::size_t compact_tail(const Candidates& c, const std::uint32_t* ids, std::size_t k, double px, double py,
                                double pz, double radius2, std::uint32_t* out, std::size_t written) {
  for (; k < c.size; ++k) {
    out[written] = ids[k];
    written += within(c.x[k] - px, c.y[k] - py, c.z[k] - pz, radius2);
  }
  return written;
}

#if defined(__GNUC__) && defined(__x86_64__)
#define PNF_HAVE_SIMD_SCANS 1  // the explicit AVX-512 and AVX2 scans below, x86-64 only
// AVX-512 versions, 16 candidates a step: two 8-wide double tests (the same operations in the
// same order as within(), so the same roundings) give a 16-bit mask; the count adds its bits,
// the compaction packs the ids it selects with one in-register compress and a full-width store
// (a compress straight to memory is microcoded and slow on some cores). `out` must have room
// for 16 ids past the last one kept; the tail (under 16) goes through within() itself.
__attribute__((target("avx512f"))) inline __mmask8 within8(const Candidates& c, std::size_t at, __m512d px, __m512d py,
                                                           __m512d pz, __m512d radius2) {
  const __m512d dx = _mm512_sub_pd(_mm512_loadu_pd(c.x + at), px);
  const __m512d dy = _mm512_sub_pd(_mm512_loadu_pd(c.y + at), py);
  const __m512d dz = _mm512_sub_pd(_mm512_loadu_pd(c.z + at), pz);
  const __m512d d2 = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy)), _mm512_mul_pd(dz, dz));
  return _mm512_cmp_pd_mask(d2, radius2, _CMP_LE_OQ);
}

__attribute__((target("avx512f"))) inline __mmask16 within16(const Candidates& c, std::size_t k, __m512d px, __m512d py,
                                                             __m512d pz, __m512d radius2) {
  return __mmask16(unsigned(within8(c, k, px, py, pz, radius2)) |
                   (unsigned(within8(c, k + 8, px, py, pz, radius2)) << 8));
}

__attribute__((target("avx512f"))) std::uint32_t count_scan_avx512(const Candidates& c, double px, double py, double pz,
                                                                   double radius2) {
  const __m512d vx = _mm512_set1_pd(px), vy = _mm512_set1_pd(py), vz = _mm512_set1_pd(pz), vr = _mm512_set1_pd(radius2);
  std::uint32_t n = 0;
  std::size_t k = 0;
  for (; k + 16 <= c.size; k += 16) n += std::uint32_t(__builtin_popcount(unsigned(within16(c, k, vx, vy, vz, vr))));
  return n + count_tail(c, k, px, py, pz, radius2);
}

__attribute__((target("avx512f"))) std::size_t compact_scan_avx512(const Candidates& c, const std::uint32_t* ids,
                                                                   double px, double py, double pz, double radius2,
                                                                   std::uint32_t* out) {
  const __m512d vx = _mm512_set1_pd(px), vy = _mm512_set1_pd(py), vz = _mm512_set1_pd(pz), vr = _mm512_set1_pd(radius2);
  std::size_t written = 0, k = 0;
  for (; k + 16 <= c.size; k += 16) {
    const __mmask16 keep = within16(c, k, vx, vy, vz, vr);
    const __m512i packed = _mm512_maskz_compress_epi32(keep, _mm512_loadu_si512(ids + k));
    _mm512_storeu_si512(out + written, packed);
    written += std::size_t(__builtin_popcount(unsigned(keep)));
  }
  return compact_tail(c, ids, k, px, py, pz, radius2, out, written);
}

bool cpu_has_avx512() {
  static const bool has = __builtin_cpu_supports("avx512f");
  return has;
}

// AVX2 versions for CPUs without AVX-512, 8 candidates a step: two 4-wide double tests (again
// the same operations in the same order as within(); target avx2 enables no FMA, so nothing is
// contracted) give an 8-bit mask. AVX2 has no compress: the compaction permutes the 8 ids by a
// table of the kept lanes' positions per mask (2 KB) and stores all 8, so `out` must have room
// for 8 ids past the last one kept.
__attribute__((target("avx2"))) inline unsigned within8_avx2(const Candidates& c, std::size_t at, __m256d px,
                                                             __m256d py, __m256d pz, __m256d radius2) {
  unsigned mask = 0;
  for (int half = 0; half < 2; ++half) {
    const std::size_t k = at + 4 * std::size_t(half);
    const __m256d dx = _mm256_sub_pd(_mm256_loadu_pd(c.x + k), px);
    const __m256d dy = _mm256_sub_pd(_mm256_loadu_pd(c.y + k), py);
    const __m256d dz = _mm256_sub_pd(_mm256_loadu_pd(c.z + k), pz);
    const __m256d d2 =
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz));
    mask |= unsigned(_mm256_movemask_pd(_mm256_cmp_pd(d2, radius2, _CMP_LE_OQ))) << (4 * half);
  }
  return mask;
}

__attribute__((target("avx2"))) std::uint32_t count_scan_avx2(const Candidates& c, double px, double py, double pz,
                                                              double radius2) {
  const __m256d vx = _mm256_set1_pd(px), vy = _mm256_set1_pd(py), vz = _mm256_set1_pd(pz), vr = _mm256_set1_pd(radius2);
  std::uint32_t n = 0;
  std::size_t k = 0;
  for (; k + 8 <= c.size; k += 8) n += std::uint32_t(__builtin_popcount(within8_avx2(c, k, vx, vy, vz, vr)));
  return n + count_tail(c, k, px, py, pz, radius2);
}

// For each 8-bit mask, the positions of its set bits in order, one byte each, the rest 0.
struct CompressTable {
  std::uint64_t lanes[256];
  CompressTable() {
    for (unsigned m = 0; m < 256; ++m) {
      std::uint64_t v = 0;
      int out = 0;
      for (unsigned b = 0; b < 8; ++b) {
        if (m & (1u << b)) v |= std::uint64_t(b) << (8 * out++);
      }
      lanes[m] = v;
    }
  }
};

__attribute__((target("avx2"))) std::size_t compact_scan_avx2(const Candidates& c, const std::uint32_t* ids, double px,
                                                              double py, double pz, double radius2,
                                                              std::uint32_t* out) {
  static const CompressTable table;
  const __m256d vx = _mm256_set1_pd(px), vy = _mm256_set1_pd(py), vz = _mm256_set1_pd(pz), vr = _mm256_set1_pd(radius2);
  std::size_t written = 0, k = 0;
  for (; k + 8 <= c.size; k += 8) {
    const unsigned keep = within8_avx2(c, k, vx, vy, vz, vr);
    const __m256i order = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(static_cast<long long>(table.lanes[keep])));
    const __m256i packed =
        _mm256_permutevar8x32_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(ids + k)), order);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + written), packed);
    written += std::size_t(__builtin_popcount(keep));
  }
  return compact_tail(c, ids, k, px, py, pz, radius2, out, written);
}

bool cpu_has_avx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}
#endif

}  // namespace

std::uint32_t count_candidates_within(const Candidates& c, double px, double py, double pz, double radius2,
                                      const SpatialIndex::ListTuning& tuning) {
#ifdef PNF_HAVE_SIMD_SCANS
  if (tuning.avx512_scan && cpu_has_avx512()) return count_scan_avx512(c, px, py, pz, radius2);
  if (tuning.avx2_scan && cpu_has_avx2()) return count_scan_avx2(c, px, py, pz, radius2);
#endif
  return tuning.wide_scan ? count_scan_wide(c, px, py, pz, radius2) : count_scan_plain(c, px, py, pz, radius2);
}

std::size_t compact_candidates_within(const Candidates& c, const std::uint32_t* ids, double px, double py, double pz,
                                      double radius2, const SpatialIndex::ListTuning& tuning, std::uint32_t* out) {
#ifdef PNF_HAVE_SIMD_SCANS
  if (tuning.avx512_scan && cpu_has_avx512()) return compact_scan_avx512(c, ids, px, py, pz, radius2, out);
  if (tuning.avx2_scan && cpu_has_avx2()) return compact_scan_avx2(c, ids, px, py, pz, radius2, out);
#endif
  // Plain even where wide_scan is set: the auto-vectorised flags-then-compact variant lost to
  // this loop on the dog (docs/performance.md).
  return compact_tail(c, ids, 0, px, py, pz, radius2, out, 0);
}

}  // namespace pnf::detail
