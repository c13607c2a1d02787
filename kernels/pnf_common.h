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
typedef uint pnf_index;   /* a point id: 32 bits, clouds are limited to 2^32 - 1 points */
typedef ulong pnf_offset; /* a CSR offset: 64 bits, the pair count can pass 2^32 */
#define pnf_exp exp
#define pnf_sqrt sqrt
/* max(a, lo), and v where a >= lo else 0, lane by lane, without a branch (select, fmax). */
#define pnf_lane_max(a, lo) fmax((a), (pnf_lane)(lo))
#define pnf_lane_keep_ge(v, a, lo) select((pnf_lane)0, (v), (a) >= (pnf_lane)(lo))
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
PNF_FN pnf_lane pnf_lane_max(pnf_lane a, pnf_lane lo) { return a > lo ? a : lo; }
PNF_FN pnf_lane pnf_lane_keep_ge(pnf_lane v, pnf_lane a, pnf_lane lo) { return a >= lo ? v : 0; }
#endif

/* The spatial weight f is truncated at this many sigma_f: neighbours reach 2 sigma_f (SPEC). */
#define PNF_SUPPORT_IN_SIGMA_F 2

/* A weight whose exponent is below this is cut to zero, on every device and in the reference
 * (SPEC, "Numerics": denormals must not set the speed). exp(-64) = 1.6e-28: far from float's
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

/* |C n| below this fraction of |J|_F^2 means J is degenerate, and the input normal is kept (SPEC,
 * "The normal update"). |J|_F^2 is the scale C's entries are computed at (each is a difference
 * of products of two entries of J), so it also sets their rounding: for a rank-1 J, whose C is 0
 * exactly, the computed C is that rounding, and |C| itself is no scale to compare with. J comes
 * from sums over up to ~1000 neighbours, about 1e-6 relative error in float and 1e-14 in double;
 * each threshold sits 100x above its type's error and far below a plane's 0.5 (J = I - n n^T,
 * C n = n). The threshold follows the scalar type: SPEC's 1e-12 is below float's rounding. */
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
 * w = exp(-(|p - x|^2 * f + ((p - x).n)^2 * g)): the two Gaussians of SPEC share one exp. */
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

PNF_FN pnf_vec3 pnf_load_vec3(PNF_GLOBAL const pnf_real* a, pnf_index i) {
  return pnf_make_vec3(a[3 * (pnf_offset)i], a[3 * (pnf_offset)i + 1], a[3 * (pnf_offset)i + 2]);
}

PNF_FN pnf_real pnf_dot3(pnf_vec3 a, pnf_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

PNF_FN pnf_vec3 pnf_cross3(pnf_vec3 a, pnf_vec3 b) {
  return pnf_make_vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

PNF_FN pnf_vec3 pnf_scale3(pnf_vec3 a, pnf_real s) { return pnf_make_vec3(a.x * s, a.y * s, a.z * s); }

PNF_FN pnf_vec3 pnf_add3(pnf_vec3 a, pnf_vec3 b) { return pnf_make_vec3(a.x + b.x, a.y + b.y, a.z + b.z); }

/* Dual arithmetic: just what F needs. */
PNF_FN pnf_dual pnf_dual_const(pnf_real v) {
  pnf_dual r;
  r.v = v;
  r.d[0] = 0;
  r.d[1] = 0;
  r.d[2] = 0;
  return r;
}

/* The k-th coordinate of a query point, seeded with dx_k/dx_k = 1. */
PNF_FN pnf_dual pnf_dual_var(pnf_real v, int k) {
  pnf_dual r = pnf_dual_const(v);
  r.d[k] = 1;
  return r;
}

PNF_FN pnf_dual pnf_dual_add(pnf_dual a, pnf_dual b) {
  pnf_dual r;
  r.v = a.v + b.v;
  for (int k = 0; k < 3; ++k) r.d[k] = a.d[k] + b.d[k];
  return r;
}

PNF_FN pnf_dual pnf_dual_mul(pnf_dual a, pnf_dual b) {
  pnf_dual r;
  r.v = a.v * b.v;
  for (int k = 0; k < 3; ++k) r.d[k] = a.d[k] * b.v + a.v * b.d[k];
  return r;
}

PNF_FN pnf_dual pnf_dual_scale(pnf_dual a, pnf_real s) {
  pnf_dual r;
  r.v = a.v * s;
  for (int k = 0; k < 3; ++k) r.d[k] = a.d[k] * s;
  return r;
}

/* c - a for a constant c. */
PNF_FN pnf_dual pnf_dual_rsub(pnf_real c, pnf_dual a) {
  pnf_dual r;
  r.v = c - a.v;
  for (int k = 0; k < 3; ++k) r.d[k] = -a.d[k];
  return r;
}

PNF_FN pnf_dual pnf_dual_div(pnf_dual a, pnf_dual b) {
  pnf_dual r;
  pnf_real inv = (pnf_real)1 / b.v;
  r.v = a.v * inv;
  for (int k = 0; k < 3; ++k) r.d[k] = (a.d[k] - r.v * b.d[k]) * inv;
  return r;
}

PNF_FN pnf_dual pnf_dual_exp(pnf_dual a) {
  pnf_dual r;
  r.v = pnf_exp(a.v);
  for (int k = 0; k < 3; ++k) r.d[k] = r.v * a.d[k];
  return r;
}

/* The query point x = p as a dual vector: value p, Jacobian dx/dx = I. */
PNF_FN pnf_dvec3 pnf_dvec3_seed(pnf_vec3 p) {
  pnf_dvec3 r;
  r.x = pnf_dual_var(p.x, 0);
  r.y = pnf_dual_var(p.y, 1);
  r.z = pnf_dual_var(p.z, 2);
  return r;
}

/* A dual number per lane: PNF_LANES neighbours' values and partials side by side. */
typedef struct {
  pnf_lane v, d0, d1, d2;
} pnf_ldual;

/* c - x for lanes c and a scalar dual x (broadcast). */
PNF_FN pnf_ldual pnf_ldual_rsub(pnf_lane c, pnf_dual x) {
  pnf_ldual r;
  r.v = c - x.v;
  r.d0 = -x.d[0];
  r.d1 = -x.d[1];
  r.d2 = -x.d[2];
  return r;
}

/* x + a for a scalar dual x (broadcast) and lanes a. */
PNF_FN pnf_ldual pnf_ldual_add_scalar(pnf_dual x, pnf_ldual a) {
  pnf_ldual r;
  r.v = x.v + a.v;
  r.d0 = x.d[0] + a.d0;
  r.d1 = x.d[1] + a.d1;
  r.d2 = x.d[2] + a.d2;
  return r;
}

PNF_FN pnf_ldual pnf_ldual_add(pnf_ldual a, pnf_ldual b) {
  pnf_ldual r;
  r.v = a.v + b.v;
  r.d0 = a.d0 + b.d0;
  r.d1 = a.d1 + b.d1;
  r.d2 = a.d2 + b.d2;
  return r;
}

PNF_FN pnf_ldual pnf_ldual_mul(pnf_ldual a, pnf_ldual b) {
  pnf_ldual r;
  r.v = a.v * b.v;
  r.d0 = a.d0 * b.v + a.v * b.d0;
  r.d1 = a.d1 * b.v + a.v * b.d1;
  r.d2 = a.d2 * b.v + a.v * b.d2;
  return r;
}

/* a * s for lanes s that carry no derivative (a neighbour's normal component, a constant). */
PNF_FN pnf_ldual pnf_ldual_scale(pnf_ldual a, pnf_lane s) {
  pnf_ldual r;
  r.v = a.v * s;
  r.d0 = a.d0 * s;
  r.d1 = a.d1 * s;
  r.d2 = a.d2 * s;
  return r;
}

/* exp, cut to 0 below PNF_WEIGHT_CUT_EXPONENT: the argument is clamped first, so exp itself
 * never produces a denormal either. */
PNF_FN pnf_ldual pnf_ldual_exp_cut(pnf_ldual a) {
  pnf_ldual r;
  r.v = pnf_lane_keep_ge(pnf_exp(pnf_lane_max(a.v, PNF_WEIGHT_CUT_EXPONENT)), a.v, PNF_WEIGHT_CUT_EXPONENT);
  r.d0 = r.v * a.d0;
  r.d1 = r.v * a.d1;
  r.d2 = r.v * a.d2;
  return r;
}

PNF_FN pnf_ldual pnf_ldual_zero(void) {
  pnf_ldual r;
  r.v = 0;
  r.d0 = 0;
  r.d1 = 0;
  r.d2 = 0;
  return r;
}

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

/* The scalar dual whose value and partials are the sums over the lanes of a. */
PNF_FN pnf_dual pnf_ldual_sum(pnf_ldual a) {
  pnf_dual r;
  r.v = pnf_lane_sum(a.v);
  r.d[0] = pnf_lane_sum(a.d0);
  r.d[1] = pnf_lane_sum(a.d1);
  r.d[2] = pnf_lane_sum(a.d2);
  return r;
}

#endif /* PNF_COMMON_H */
