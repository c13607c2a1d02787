// Built with -mavx (lib/src/auto/auto.cmake); see vector_exp_wide.hpp for what it may include.
#include <immintrin.h>
#include <sleef.h>

#include "vector_exp_wide.hpp"

size_t pnf::detail::exp_in_place_avx(double* values, size_t count) {
  size_t done = 0;
  for (; done + 4 <= count; done += 4) {
    _mm256_storeu_pd(values + done, Sleef_cinz_expd4_u10avx(_mm256_loadu_pd(values + done)));
  }
  return done;
}
