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

/* The running sums of F's denominator (sum w) and numerator (sum w Pi), per lane, as duals. */
typedef struct {
  pnf_ldual w, wpx, wpy, wpz;
} pnf_sums;

PNF_FN pnf_sums pnf_sums_zero(void) {
  pnf_sums acc;
  acc.w = pnf_ldual_zero();
  acc.wpx = pnf_ldual_zero();
  acc.wpy = pnf_ldual_zero();
  acc.wpz = pnf_ldual_zero();
  return acc;
}

/* Adds PNF_LANES neighbours to the sums: their positions relative to the origin o (p - o), their
 * normals, and `valid` (1 for a neighbour, 0 for a padding lane). The query is x = o + x_local.
 * Working relative to o keeps float32 precise far from the cloud's centre: p - o is exact for
 * nearby floats, and F - o is of the size of the neighbourhood, not of the model. */
PNF_FN void pnf_accumulate(pnf_sums* acc, pnf_dvec3 x_local, pnf_lane px, pnf_lane py, pnf_lane pz, pnf_lane nx,
                           pnf_lane ny, pnf_lane nz, pnf_lane valid, pnf_coeffs c) {
  pnf_ldual dx = pnf_ldual_rsub(px, x_local.x); /* p - x */
  pnf_ldual dy = pnf_ldual_rsub(py, x_local.y);
  pnf_ldual dz = pnf_ldual_rsub(pz, x_local.z);
  pnf_ldual dist2 = pnf_ldual_add(pnf_ldual_add(pnf_ldual_mul(dx, dx), pnf_ldual_mul(dy, dy)), pnf_ldual_mul(dz, dz));
  pnf_ldual h = pnf_ldual_add(pnf_ldual_add(pnf_ldual_scale(dx, nx), pnf_ldual_scale(dy, ny)), pnf_ldual_scale(dz, nz));
  pnf_ldual exponent = pnf_ldual_add(pnf_ldual_scale(dist2, (pnf_lane)(-c.inv_two_sigma_f2)),
                                     pnf_ldual_scale(pnf_ldual_mul(h, h), (pnf_lane)(-c.inv_two_sigma_g2)));
  pnf_ldual w = pnf_ldual_scale(pnf_ldual_exp_cut(exponent), valid);
  /* Pi_p(x) - o = x_local + h n_p */
  pnf_ldual pi_x = pnf_ldual_add_scalar(x_local.x, pnf_ldual_scale(h, nx));
  pnf_ldual pi_y = pnf_ldual_add_scalar(x_local.y, pnf_ldual_scale(h, ny));
  pnf_ldual pi_z = pnf_ldual_add_scalar(x_local.z, pnf_ldual_scale(h, nz));
  acc->w = pnf_ldual_add(acc->w, w);
  acc->wpx = pnf_ldual_add(acc->wpx, pnf_ldual_mul(w, pi_x));
  acc->wpy = pnf_ldual_add(acc->wpy, pnf_ldual_mul(w, pi_y));
  acc->wpz = pnf_ldual_add(acc->wpz, pnf_ldual_mul(w, pi_z));
}

/* F - o = sum w Pi / sum w, with its Jacobian in the partials. */
PNF_FN pnf_dvec3 pnf_finish_F(pnf_sums acc) {
  pnf_dual w = pnf_ldual_sum(acc.w);
  pnf_dvec3 f;
  f.x = pnf_dual_div(pnf_ldual_sum(acc.wpx), w);
  f.y = pnf_dual_div(pnf_ldual_sum(acc.wpy), w);
  f.z = pnf_dual_div(pnf_ldual_sum(acc.wpz), w);
  return f;
}

/* Column k of J = dF/dx. */
PNF_FN pnf_vec3 pnf_jacobian_column(pnf_dvec3 f, int k) { return pnf_make_vec3(f.x.d[k], f.y.d[k], f.z.d[k]); }

/* n' = C n_s / |C n_s| with SPEC's orientation and degenerate rules. *kept is set to 1 when J is
 * degenerate and n_s is returned unchanged, to 0 otherwise. */
PNF_FN pnf_vec3 pnf_update_normal(pnf_dvec3 f, pnf_vec3 n_s, int* kept) {
  pnf_vec3 j0 = pnf_jacobian_column(f, 0);
  pnf_vec3 j1 = pnf_jacobian_column(f, 1);
  pnf_vec3 j2 = pnf_jacobian_column(f, 2);
  pnf_vec3 c0 = pnf_cross3(j1, j2);
  pnf_vec3 c1 = pnf_cross3(j2, j0);
  pnf_vec3 c2 = pnf_cross3(j0, j1);
  pnf_vec3 m = pnf_add3(pnf_add3(pnf_scale3(c0, n_s.x), pnf_scale3(c1, n_s.y)), pnf_scale3(c2, n_s.z));
  pnf_real scale = pnf_dot3(j0, j0) + pnf_dot3(j1, j1) + pnf_dot3(j2, j2);
  pnf_real len = pnf_sqrt(pnf_dot3(m, m));
  /* Written so that a NaN or a zero scale also keeps n_s. */
  *kept = !(len > (pnf_real)PNF_DEGENERATE_RELATIVE * scale) || !(len > 0);
  if (*kept) return n_s;
  m = pnf_scale3(m, (pnf_real)1 / len);
  if (pnf_dot3(m, n_s) < 0) m = pnf_scale3(m, (pnf_real)-1);
  return m;
}

#if PNF_LANES == 1
/* F(o + x_local) - o with its Jacobian, one neighbour at a time over indices[begin, end). */
PNF_FN pnf_dvec3 pnf_eval_F(pnf_dvec3 x_local, pnf_vec3 origin, PNF_GLOBAL const pnf_index* indices, pnf_offset begin,
                            pnf_offset end, PNF_GLOBAL const pnf_real* positions, PNF_GLOBAL const pnf_real* normals,
                            pnf_coeffs c) {
  pnf_sums acc = pnf_sums_zero();
  for (pnf_offset e = begin; e < end; ++e) {
    pnf_index j = indices[e];
    pnf_vec3 p = pnf_load_vec3(positions, j);
    pnf_vec3 n = pnf_load_vec3(normals, j);
    pnf_accumulate(&acc, x_local, p.x - origin.x, p.y - origin.y, p.z - origin.z, n.x, n.y, n.z, 1, c);
  }
  return pnf_finish_F(acc);
}

/* One pass for point s: its new normal from its neighbour list indices[begin, end); *kept as
 * pnf_update_normal sets it. */
PNF_FN pnf_vec3 pnf_filter_point(pnf_index s, PNF_GLOBAL const pnf_index* indices, pnf_offset begin, pnf_offset end,
                                 PNF_GLOBAL const pnf_real* positions, PNF_GLOBAL const pnf_real* normals,
                                 pnf_coeffs c, int* kept) {
  pnf_dvec3 x_local = pnf_dvec3_seed(pnf_make_vec3(0, 0, 0));
  pnf_dvec3 f = pnf_eval_F(x_local, pnf_load_vec3(positions, s), indices, begin, end, positions, normals, c);
  return pnf_update_normal(f, pnf_load_vec3(normals, s), kept);
}
#endif

#endif /* PNF_FILTER_H */
