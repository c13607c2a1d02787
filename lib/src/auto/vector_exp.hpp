// Internal to --auto: exp over an array, for the surface judge's Gaussian weights (surface_judge.cpp),
// with SLEEF's vector exp (Debian's libsleef-dev). glibc's exp, one value at a time, took about
// 5.3 ns a value here and over half of a judged score (the 8 scores of a noisy cloud's run: 0.234
// s, 0.151 s with SLEEF's); SLEEF's takes 1.2 ns with AVX-512, 1.7 with AVX, 3.5 with SSE2
// (docs/auto.md, "Time"). glibc's own vector exp needs -ffast-math and Eigen's a build for AVX2;
// the library is built for every x86-64.
#pragma once

#include <cstddef>

namespace pnf::detail {

// values[k] = exp(values[k]) for k < count, within 1 ulp, and the same bits on every CPU:
// SLEEF's consistent functions ("cinz": no FMA, one algorithm for every vector width), the widest
// this CPU runs (AVX-512: 8 values a step, AVX: 4, else SSE2: 2), the rest one at a time.
void exp_in_place(double* values, std::size_t count);

// The same with the widest set at most `widest` lanes (8, 4, 2 or 1), for the test that they agree.
void exp_in_place_at_most(double* values, std::size_t count, int widest);

}  // namespace pnf::detail
