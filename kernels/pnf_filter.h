/* pnf_filter.h: the per-point normal filter of Jones, Durand and Zwicker (2004), as pinned down
 * by SPEC.md. Shared verbatim by the OpenCL kernel (float) and the CPU reference (double).
 *
 *   Pi_p(x) = x + ((p - x).n_p) n_p
 *   w_p(x)  = exp(-|p - x|^2 / (2 sf^2)) * exp(-((p - x).n_p)^2 / (2 sg^2))
 *   F(x)    = sum_p w_p(x) Pi_p(x) / sum_p w_p(x)      over the fixed neighbour list of s
 *   J       = dF/dx at x = s, by forward-mode dual numbers
 *   n'      = C n_s / |C n_s|,  C = [J1 x J2, J2 x J0, J0 x J1] = adj(J)^T
 *
 * The truncation of f at 2 sf is the neighbour list itself: every listed neighbour was within
 * 2 sf of s when the list was built, and the list is held fixed while x moves, so F is smooth.
 * Positions and normals are arrays of 3 pnf_real per point. */
#ifndef PNF_FILTER_H
#define PNF_FILTER_H

#include "pnf_common.h"

PNF_FN pnf_coeffs pnf_make_coeffs(pnf_real sigma_f, pnf_real sigma_g) {
  pnf_coeffs c;
  c.inv_two_sigma_f2 = (pnf_real)1 / (2 * sigma_f * sigma_f);
  c.inv_two_sigma_g2 = (pnf_real)1 / (2 * sigma_g * sigma_g);
  return c;
}

/* F(x) - o with its Jacobian in the partials, over neighbours indices[begin, end), for a query
 * x = o + x_local given relative to an origin o. Working relative to o (the point being filtered)
 * keeps float32 precise far from the cloud's centre: p - o is exact for nearby floats, and F - o
 * is of the size of the neighbourhood, not of the model. J does not depend on o. */
PNF_FN pnf_dvec3 pnf_eval_F(pnf_dvec3 x_local, pnf_vec3 origin, PNF_GLOBAL const pnf_index* indices,
                            pnf_offset begin, pnf_offset end, PNF_GLOBAL const pnf_real* positions,
                            PNF_GLOBAL const pnf_real* normals, pnf_coeffs c) {
  pnf_dual sum_w = pnf_dual_const(0);
  pnf_dvec3 sum_wp;
  sum_wp.x = pnf_dual_const(0);
  sum_wp.y = pnf_dual_const(0);
  sum_wp.z = pnf_dual_const(0);
  for (pnf_offset e = begin; e < end; ++e) {
    pnf_index j = indices[e];
    pnf_vec3 p = pnf_load_vec3(positions, j);
    pnf_vec3 n = pnf_load_vec3(normals, j);
    pnf_dual dx = pnf_dual_rsub(p.x - origin.x, x_local.x); /* p - x */
    pnf_dual dy = pnf_dual_rsub(p.y - origin.y, x_local.y);
    pnf_dual dz = pnf_dual_rsub(p.z - origin.z, x_local.z);
    pnf_dual dist2 = pnf_dual_add(pnf_dual_add(pnf_dual_mul(dx, dx), pnf_dual_mul(dy, dy)), pnf_dual_mul(dz, dz));
    pnf_dual h = pnf_dual_add(pnf_dual_add(pnf_dual_scale(dx, n.x), pnf_dual_scale(dy, n.y)), pnf_dual_scale(dz, n.z));
    pnf_dual exponent = pnf_dual_add(pnf_dual_scale(dist2, -c.inv_two_sigma_f2),
                                     pnf_dual_scale(pnf_dual_mul(h, h), -c.inv_two_sigma_g2));
    pnf_dual w = pnf_dual_exp(exponent);
    /* Pi_p(x) - o = x_local + h n_p */
    pnf_dual px = pnf_dual_add(x_local.x, pnf_dual_scale(h, n.x));
    pnf_dual py = pnf_dual_add(x_local.y, pnf_dual_scale(h, n.y));
    pnf_dual pz = pnf_dual_add(x_local.z, pnf_dual_scale(h, n.z));
    sum_w = pnf_dual_add(sum_w, w);
    sum_wp.x = pnf_dual_add(sum_wp.x, pnf_dual_mul(w, px));
    sum_wp.y = pnf_dual_add(sum_wp.y, pnf_dual_mul(w, py));
    sum_wp.z = pnf_dual_add(sum_wp.z, pnf_dual_mul(w, pz));
  }
  pnf_dvec3 f;
  f.x = pnf_dual_div(sum_wp.x, sum_w);
  f.y = pnf_dual_div(sum_wp.y, sum_w);
  f.z = pnf_dual_div(sum_wp.z, sum_w);
  return f;
}

/* Column k of J = dF/dx. */
PNF_FN pnf_vec3 pnf_jacobian_column(pnf_dvec3 f, int k) { return pnf_make_vec3(f.x.d[k], f.y.d[k], f.z.d[k]); }

/* n' = C n_s / |C n_s| with SPEC's orientation and degenerate rules. */
PNF_FN pnf_vec3 pnf_update_normal(pnf_dvec3 f, pnf_vec3 n_s) {
  pnf_vec3 j0 = pnf_jacobian_column(f, 0);
  pnf_vec3 j1 = pnf_jacobian_column(f, 1);
  pnf_vec3 j2 = pnf_jacobian_column(f, 2);
  pnf_vec3 c0 = pnf_cross3(j1, j2);
  pnf_vec3 c1 = pnf_cross3(j2, j0);
  pnf_vec3 c2 = pnf_cross3(j0, j1);
  pnf_vec3 m = pnf_add3(pnf_add3(pnf_scale3(c0, n_s.x), pnf_scale3(c1, n_s.y)), pnf_scale3(c2, n_s.z));
  pnf_real scale = pnf_sqrt(pnf_dot3(c0, c0) + pnf_dot3(c1, c1) + pnf_dot3(c2, c2));
  pnf_real len = pnf_sqrt(pnf_dot3(m, m));
  /* Written so that a NaN or a zero scale also keeps n_s. */
  if (!(len > (pnf_real)PNF_DEGENERATE_RELATIVE * scale) || !(len > 0)) return n_s;
  m = pnf_scale3(m, (pnf_real)1 / len);
  if (pnf_dot3(m, n_s) < 0) m = pnf_scale3(m, (pnf_real)-1);
  return m;
}

/* One pass for point s: its new normal from its neighbour list indices[begin, end). */
PNF_FN pnf_vec3 pnf_filter_point(pnf_index s, PNF_GLOBAL const pnf_index* indices, pnf_offset begin,
                                 pnf_offset end, PNF_GLOBAL const pnf_real* positions,
                                 PNF_GLOBAL const pnf_real* normals, pnf_coeffs c) {
  pnf_dvec3 x_local = pnf_dvec3_seed(pnf_make_vec3(0, 0, 0));
  pnf_dvec3 f = pnf_eval_F(x_local, pnf_load_vec3(positions, s), indices, begin, end, positions, normals, c);
  return pnf_update_normal(f, pnf_load_vec3(normals, s));
}

#endif /* PNF_FILTER_H */
