// exp over an array with SLEEF (vector_exp.hpp); the AVX-512 and AVX steps are in their own files,
// built with those instruction sets, and run only where the CPU has them.
#include "vector_exp.hpp"

#if defined(__x86_64__)
#include <immintrin.h>
#endif
#include <sleef.h>

#include "vector_exp_wide.hpp"

namespace pnf::detail {
namespace {

int widest_lanes() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  static const int lanes = __builtin_cpu_supports("avx512f") ? 8 : __builtin_cpu_supports("avx") ? 4 : 2;
  return lanes;
#else
  return 1;
#endif
}

}  // namespace

void exp_in_place_at_most(double* values, std::size_t count, int widest) {
  const int lanes = widest < widest_lanes() ? widest : widest_lanes();
  std::size_t done = 0;
#if defined(__x86_64__)
  if (lanes == 8) done = exp_in_place_avx512(values, count);
  if (lanes == 4) done = exp_in_place_avx(values, count);
  if (lanes == 2) {
    for (; done + 2 <= count; done += 2)
      _mm_storeu_pd(values + done, Sleef_cinz_expd2_u10sse2(_mm_loadu_pd(values + done)));
  }
#endif
  for (; done < count; ++done) values[done] = Sleef_cinz_expd1_u10purec(values[done]);
}

void exp_in_place(double* values, std::size_t count) { exp_in_place_at_most(values, count, 8); }

}  // namespace pnf::detail
