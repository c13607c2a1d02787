// Internal to vector_exp.cpp: its AVX-512 and AVX steps, each in a file built with that instruction
// set (vector_exp_avx512.cpp, vector_exp_avx.cpp; x86-64 only). Those files include nothing but
// this, <immintrin.h> and <sleef.h>: an inline function of a shared header compiled there could be
// the copy the linker keeps, and run on a CPU without the instructions.
#pragma once

#include <stddef.h>

namespace pnf::detail {

// exp in place of values[0, k) for the largest k <= count that is a whole number of steps (8 or
// 4 values); returns k. Only on a CPU with AVX-512F, or AVX.
size_t exp_in_place_avx512(double* values, size_t count);
size_t exp_in_place_avx(double* values, size_t count);

}  // namespace pnf::detail
