// PNF_WIDE_CLONES before a function builds it three times, for the build's baseline (SSE2 on
// x86-64), AVX2 and AVX-512, the copy run picked once at load time by the CPU (GCC's
// target_clones; plain elsewhere). For loops the compiler vectorises: the library is compiled
// without floating-point contraction (-std=c++17), so every copy rounds as the plain one does
// where its arithmetic is element by element, and the results are the same bits on every CPU.
#pragma once

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define PNF_WIDE_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define PNF_WIDE_CLONES
#endif
