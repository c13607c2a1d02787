// Built with -mavx512f (lib/src/auto/auto.cmake); see vector_exp_wide.hpp for what it may include.
#include <immintrin.h>
#include <sleef.h>

#include "vector_exp_wide.hpp"

size_t pnf::detail::exp_in_place_avx512(double* values, size_t count) {
  size_t done = 0;
  for (; done + 8 <= count; done += 8) {
    _mm512_storeu_pd(values + done, Sleef_cinz_expd8_u10avx512fnofma(_mm512_loadu_pd(values + done)));
  }
  return done;
}
