/* pnf_common.h: the types and qualifiers shared by the OpenCL kernels and the C++ reference.
 *
 * This file is written in the common subset of OpenCL C 1.2 and C++17: plain structs, free
 * functions behind PNF_FN, one scalar type pnf_real (float in kernels, double in the reference).
 * Every name carries the pnf_ / PNF_ prefix because OpenCL C has no namespaces. */
#ifndef PNF_COMMON_H
#define PNF_COMMON_H

#ifdef __OPENCL_VERSION__
#define PNF_FN static inline
#define PNF_GLOBAL __global
typedef float pnf_real;
typedef uint pnf_index;   /* a point id: 32 bits, clouds are limited to 2^32 - 1 points */
typedef ulong pnf_offset; /* a CSR offset: 64 bits, the pair count can pass 2^32 */
#define pnf_exp exp
#define pnf_sqrt sqrt
#else
#include <cmath>
#include <cstdint>
#define PNF_FN static inline
#define PNF_GLOBAL
typedef double pnf_real;
typedef std::uint32_t pnf_index;
typedef std::uint64_t pnf_offset;
#define pnf_exp std::exp
#define pnf_sqrt std::sqrt
#endif

/* The spatial weight f is truncated at this many sigma_f: neighbours reach 2 sigma_f (SPEC). */
#define PNF_SUPPORT_IN_SIGMA_F 2

/* |C n| below this fraction of the Frobenius norm of C means J is degenerate, and the input
 * normal is kept (SPEC, "The normal update"). */
#define PNF_DEGENERATE_RELATIVE 1e-12

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

#endif /* PNF_COMMON_H */
