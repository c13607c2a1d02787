/* pnf_common.h: the types and qualifiers shared by the OpenCL kernels and the C++ reference.
 *
 * This file is written in the common subset of OpenCL C 1.2 and C++17: plain structs, free
 * functions behind PNF_FN, one scalar type pnf_real (float in kernels, double in the reference).
 * Every name carries the pnf_ / PNF_ prefix because OpenCL C has no namespaces. */
#ifndef PNF_COMMON_H
#define PNF_COMMON_H

/* PNF_LANES: how many neighbours the kernel takes per step, as one OpenCL vector (a build
 * option, chosen per device type: wide on CPUs, where PoCL does not vectorise across
 * work-items, 1 on GPUs, whose threads are the vector lanes). The reference uses 1. */
#ifndef PNF_LANES
#define PNF_LANES 1
#endif

#ifdef __OPENCL_VERSION__
#define PNF_FN static inline
#define PNF_GLOBAL __global
typedef float pnf_real;
#if PNF_LANES == 1
typedef float pnf_lane;
#elif PNF_LANES == 4
typedef float4 pnf_lane;
#elif PNF_LANES == 8
typedef float8 pnf_lane;
#elif PNF_LANES == 16
typedef float16 pnf_lane;
#else
#error "PNF_LANES must be 1, 4, 8 or 16"
#endif
typedef uint pnf_index;   /* a point id: 32 bits; clouds are limited to 2^32 - 2 points (cloud_checks.hpp) */
typedef ulong pnf_offset; /* a CSR offset: 64 bits, the pair count can pass 2^32 */
#define pnf_exp exp
#define pnf_sqrt sqrt
/* A point's position or normal as stored on the device: x, y, z and one unused float, so that a
 * neighbour is one aligned 16-byte load. */
typedef float4 pnf_real4;
/* max(a, lo), and v where a >= lo else 0, lane by lane, without a branch (select, fmax). */
#define pnf_lane_max(a, lo) fmax((a), (pnf_lane)(lo))
#define pnf_lane_keep_ge(v, a, lo) select((pnf_lane)0, (v), (a) >= (pnf_lane)(lo))
/* PNF_LANES consecutive pnf_real of a private array as one pnf_lane. */
#if PNF_LANES == 1
#define pnf_lane_load(a) ((a)[0])
#elif PNF_LANES == 4
#define pnf_lane_load(a) vload4(0, (a))
#elif PNF_LANES == 8
#define pnf_lane_load(a) vload8(0, (a))
#else
#define pnf_lane_load(a) vload16(0, (a))
#endif
#else
#include <cmath>
#include <cstdint>
#define PNF_FN static inline
#define PNF_GLOBAL
typedef double pnf_real;
#if PNF_LANES != 1
#error "the C++ reference runs one lane"
#endif
typedef double pnf_lane;
typedef std::uint32_t pnf_index;
typedef std::uint64_t pnf_offset;
#define pnf_exp std::exp
#define pnf_sqrt std::sqrt
typedef struct {
  double x, y, z, w;
} pnf_real4;
PNF_FN pnf_lane pnf_lane_max(pnf_lane a, pnf_lane lo) { return a > lo ? a : lo; }
PNF_FN pnf_lane pnf_lane_keep_ge(pnf_lane v, pnf_lane a, pnf_lane lo) { return a >= lo ? v : 0; }
PNF_FN pnf_lane pnf_lane_load(const pnf_real* a) { return a[0]; }
#endif

/* The spatial weight f is truncated at this many sigma_f: neighbours reach 2 sigma_f (docs/method.md, "Reach"). */
#define PNF_SUPPORT_IN_SIGMA_F 2

/* A weight whose exponent is below this is cut to zero, on every device and in the reference
 * (docs/method.md, "The weight cut": denormals must not set the speed). exp(-64) = 1.6e-28: far from float's
 * denormal range (below 1.2e-38), with ten decades of headroom so that the weight's products in
 * the sums (w h, w d, ...) stay normal floats too, and so small next to the self weight 1 that
 * even 1000 such neighbours (1.6e-25 relative) are below double's rounding: the cut does not
 * change the reference's function to its own precision. Without it, neighbours across a crease
 * ((h / sigma_g)^2 far above 1) give denormal weights, and denormal arithmetic is slow on x86
 * (3x on the dog setting; docs/performance.md). A build option (-cl-denorms-are-zero) would be a
 * request a driver may ignore; this cut is arithmetic, so it holds everywhere. Overridable with
 * -D only to measure it (the bench's --kernel-options). */
#ifndef PNF_WEIGHT_CUT_EXPONENT
#define PNF_WEIGHT_CUT_EXPONENT -64
#endif

/* |C n| below this fraction of |J|_F^2 means J is degenerate, and the input normal is kept (docs/method.md,
 * "The normal update"). |J|_F^2 is the scale C's entries are computed at (each is a difference
 * of products of two entries of J), so it also sets their rounding: for a rank-1 J, whose C is 0
 * exactly, the computed C is that rounding, and |C| itself is no scale to compare with. J comes
 * from sums over up to ~1000 neighbours, about 1e-6 relative error in float and 1e-14 in double;
 * each threshold sits 100x above its type's error and far below a plane's 0.5 (J = I - n n^T,
 * C n = n). The threshold follows the scalar type: double's 1e-12 is below float's rounding. */
#ifdef __OPENCL_VERSION__
#define PNF_DEGENERATE_RELATIVE 1e-4f
#else
#define PNF_DEGENERATE_RELATIVE 1e-12
#endif

typedef struct {
  pnf_real x, y, z;
} pnf_vec3;

/* A dual number: value v and its partial derivatives d[k] = dv/dx_k, k = 0..2. */
typedef struct {
  pnf_real v;
  pnf_real d[3];
} pnf_dual;

typedef struct {
  pnf_dual x, y, z;
} pnf_dvec3;

/* The Gaussian widths as the exponent coefficients 1 / (2 sigma^2), in model units^-2.
 * w = exp(-(|p - x|^2 * f + ((p - x).n)^2 * g)): the two Gaussians of docs/method.md share one exp. */
typedef struct {
  pnf_real inv_two_sigma_f2;
  pnf_real inv_two_sigma_g2;
} pnf_coeffs;

PNF_FN pnf_vec3 pnf_make_vec3(pnf_real x, pnf_real y, pnf_real z) {
  pnf_vec3 r;
  r.x = x;
  r.y = y;
  r.z = z;
  return r;
}

PNF_FN pnf_vec3 pnf_vec3_of(pnf_real4 a) { return pnf_make_vec3(a.x, a.y, a.z); }

PNF_FN pnf_real pnf_dot3(pnf_vec3 a, pnf_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

PNF_FN pnf_vec3 pnf_cross3(pnf_vec3 a, pnf_vec3 b) {
  return pnf_make_vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

PNF_FN pnf_vec3 pnf_scale3(pnf_vec3 a, pnf_real s) { return pnf_make_vec3(a.x * s, a.y * s, a.z * s); }

PNF_FN pnf_vec3 pnf_add3(pnf_vec3 a, pnf_vec3 b) { return pnf_make_vec3(a.x + b.x, a.y + b.y, a.z + b.z); }

/* Dual arithmetic (three partials): what F's final division needs. */
PNF_FN pnf_dual pnf_dual_const(pnf_real v) {
  pnf_dual r;
  r.v = v;
  r.d[0] = 0;
  r.d[1] = 0;
  r.d[2] = 0;
  return r;
}

PNF_FN pnf_dual pnf_dual_div(pnf_dual a, pnf_dual b) {
  pnf_dual r;
  pnf_real inv = (pnf_real)1 / b.v;
  r.v = a.v * inv;
  for (int k = 0; k < 3; ++k) r.d[k] = (a.d[k] - r.v * b.d[k]) * inv;
  return r;
}

/* A dual number over span{d, n}, per lane. For a neighbour p of normal n and the query x, with
 * d = p - x, every scalar of F's per-pair arithmetic has its gradient (d/dx) in span{d, n}:
 * |d|^2 has -2 d, h = d.n has -n, and sums, products and exp of such scalars stay there. So a
 * dual carries the value v and two coefficients, gradient = a d + b n, instead of three partials;
 * the gradients are expanded to x, y, z only where they are added into the sums (pnf_filter.h). */
typedef struct {
  pnf_lane v, a, b;
} pnf_sdual;

PNF_FN pnf_sdual pnf_sdual_make(pnf_lane v, pnf_lane a, pnf_lane b) {
  pnf_sdual r;
  r.v = v;
  r.a = a;
  r.b = b;
  return r;
}

/* exp(e), cut to 0 where e < cut (PNF_WEIGHT_CUT_EXPONENT, or above 0 to drop a padding lane).
 * The argument is clamped first, so exp itself never produces a denormal. Gradient: exp(e) grad e. */
PNF_FN pnf_sdual pnf_sdual_exp_cut(pnf_sdual e, pnf_lane cut) {
  pnf_lane w = pnf_lane_keep_ge(pnf_exp(pnf_lane_max(e.v, PNF_WEIGHT_CUT_EXPONENT)), e.v, cut);
  return pnf_sdual_make(w, w * e.a, w * e.b);
}

/* u h for the plane distance h = d.n, whose gradient is -n: grad(u h) = h grad u - u n. */
PNF_FN pnf_sdual pnf_sdual_mul_h(pnf_sdual u, pnf_lane h) { return pnf_sdual_make(u.v * h, u.a * h, u.b * h - u.v); }

/* The sum of the lanes of v. */
PNF_FN pnf_real pnf_lane_sum(pnf_lane v) {
#if PNF_LANES == 1
  return v;
#elif PNF_LANES == 4
  return (v.x + v.y) + (v.z + v.w);
#elif PNF_LANES == 8
  float4 h = v.lo + v.hi;
  return (h.x + h.y) + (h.z + h.w);
#else
  float8 q = v.lo + v.hi;
  float4 h = q.lo + q.hi;
  return (h.x + h.y) + (h.z + h.w);
#endif
}

/* Gathers for the wide kernels: a step's neighbours are loaded as float4 rows and transposed by
 * shuffles into x, y and z columns, rather than built lane by lane (data movement only: the
 * arithmetic is the shared pnf_accumulate). Two shapes of the same transpose (docs/performance.md):
 *   pnf_gather8_inlane  4x4 transposes inside the 128-bit halves, one unpack or move-half
 *                       instruction each; two of them make the 16-lane gather. The default on
 *                       every device: 1.05-1.2x faster than pnf_gather16 on AVX2 and, once forced
 *                       inline, 1.1-1.15x on AVX-512;
 *   pnf_gather16        four float16 of four rows, shuffles across the 128-bit halves
 *                       (PNF_GATHER_IN_HALVES=0, to measure it).
 * pnf_gather_step is the one a build uses. PNF_ROW_GATHER=0 (the bench's --kernel-options)
 * restores the lane-by-lane gather, to measure it. */
#if defined(__OPENCL_VERSION__) && (PNF_LANES == 16 || PNF_LANES == 8)
#ifndef PNF_ROW_GATHER
#define PNF_ROW_GATHER 1
#endif
#ifndef PNF_GATHER_IN_HALVES
#define PNF_GATHER_IN_HALVES 1
#endif
/* Forced inline: left to its inliner, PoCL's compiler made the gather a call, and around each call
 * the step's live vectors went to the stack and back (docs/performance.md). PNF_INLINE_GATHER=0
 * restores the hint alone, to measure it. */
#ifndef PNF_INLINE_GATHER
#define PNF_INLINE_GATHER 1
#endif
#if PNF_INLINE_GATHER
#define PNF_GATHER_FN static inline __attribute__((always_inline))
#else
#define PNF_GATHER_FN PNF_FN
#endif
/* Rows a[ids[0..16)] (x, y, z, unused) as their x, y and z columns. */
PNF_GATHER_FN void pnf_gather16(__global const float4* a, __global const uint* ids, float16* x, float16* y,
                                float16* z) {
  const float16 r0 = (float16)(a[ids[0]], a[ids[1]], a[ids[2]], a[ids[3]]);
  const float16 r1 = (float16)(a[ids[4]], a[ids[5]], a[ids[6]], a[ids[7]]);
  const float16 r2 = (float16)(a[ids[8]], a[ids[9]], a[ids[10]], a[ids[11]]);
  const float16 r3 = (float16)(a[ids[12]], a[ids[13]], a[ids[14]], a[ids[15]]);
  /* x of rows 0-7 then y of rows 0-7; the same for rows 8-15; z (and the unused w) likewise. */
  const uint16 xy = (uint16)(0, 4, 8, 12, 16, 20, 24, 28, 1, 5, 9, 13, 17, 21, 25, 29);
  const uint16 zw = (uint16)(2, 6, 10, 14, 18, 22, 26, 30, 3, 7, 11, 15, 19, 23, 27, 31);
  const float16 xy01 = shuffle2(r0, r1, xy), xy23 = shuffle2(r2, r3, xy);
  const float16 zw01 = shuffle2(r0, r1, zw), zw23 = shuffle2(r2, r3, zw);
  const uint16 lo = (uint16)(0, 1, 2, 3, 4, 5, 6, 7, 16, 17, 18, 19, 20, 21, 22, 23);
  const uint16 hi = (uint16)(8, 9, 10, 11, 12, 13, 14, 15, 24, 25, 26, 27, 28, 29, 30, 31);
  *x = shuffle2(xy01, xy23, lo);
  *y = shuffle2(xy01, xy23, hi);
  *z = shuffle2(zw01, zw23, lo);
}

/* Rows a[ids[0..8)] as columns, in the lane order 0 2 4 6 1 3 5 7: the same order for every
 * column, and a step's lanes are only summed. */
PNF_GATHER_FN void pnf_gather8_inlane(__global const float4* a, __global const uint* ids, float8* x, float8* y,
                                      float8* z) {
  const float8 r0 = (float8)(a[ids[0]], a[ids[1]]);
  const float8 r1 = (float8)(a[ids[2]], a[ids[3]]);
  const float8 r2 = (float8)(a[ids[4]], a[ids[5]]);
  const float8 r3 = (float8)(a[ids[6]], a[ids[7]]);
  const uint8 unpack_lo = (uint8)(0, 8, 1, 9, 4, 12, 5, 13);
  const uint8 unpack_hi = (uint8)(2, 10, 3, 11, 6, 14, 7, 15);
  const float8 t0 = shuffle2(r0, r1, unpack_lo), t1 = shuffle2(r2, r3, unpack_lo);
  const float8 t2 = shuffle2(r0, r1, unpack_hi), t3 = shuffle2(r2, r3, unpack_hi);
  const uint8 move_lo = (uint8)(0, 1, 8, 9, 4, 5, 12, 13);
  const uint8 move_hi = (uint8)(2, 3, 10, 11, 6, 7, 14, 15);
  *x = shuffle2(t0, t1, move_lo);
  *y = shuffle2(t0, t1, move_hi);
  *z = shuffle2(t2, t3, move_lo);
}

PNF_GATHER_FN void pnf_gather16_inlane(__global const float4* a, __global const uint* ids, float16* x, float16* y,
                                       float16* z) {
  float8 x0, y0, z0, x1, y1, z1;
  pnf_gather8_inlane(a, ids, &x0, &y0, &z0);
  pnf_gather8_inlane(a, ids + 8, &x1, &y1, &z1);
  *x = (float16)(x0, x1);
  *y = (float16)(y0, y1);
  *z = (float16)(z0, z1);
}

#if PNF_LANES == 8
#define pnf_gather_step pnf_gather8_inlane
#elif PNF_GATHER_IN_HALVES
#define pnf_gather_step pnf_gather16_inlane
#else
#define pnf_gather_step pnf_gather16
#endif
#else
#define PNF_ROW_GATHER 0
#endif

#endif /* PNF_COMMON_H */
