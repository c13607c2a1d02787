/* pnf_filter.h: the per-point normal filter of Jones, Durand and Zwicker (2004), as pinned down
 * by docs/method.md. Shared verbatim by the OpenCL kernel (float, PNF_LANES neighbours a step) and the
 * CPU reference (double, one lane): the neighbour loop below is the same code for both.
 *
 *   Pi_p(x) = x + ((p - x).n_p) n_p
 *   w_p(x)  = exp(-|p - x|^2 / (2 sf^2)) * exp(-((p - x).n_p)^2 / (2 sg^2))
 *   F(x)    = sum_p w_p(x) Pi_p(x) / sum_p w_p(x)      over the fixed neighbour list of s
 *   J       = dF/dx at x = s, by forward-mode dual numbers
 *   n'      = C n_s / |C n_s|,  C = [J1 x J2, J2 x J0, J0 x J1] = adj(J)^T
 *
 * The truncation of f at 2 sf is the neighbour list itself: every listed neighbour was within
 * 2 sf of s when the list was built, and the list is held fixed while x moves, so F is smooth.
 * Positions and normals are arrays of pnf_real4 (x, y, z, unused) per point.
 *
 * Forward mode over span{d, n} (pnf_sdual, pnf_common.h). Per pair, with d = p - x, h = d.n:
 *   E = -(f |d|^2 + g h^2)           grad E = 2f d + 2g h n
 *   w = exp(E)                        grad w = w grad E
 *   q = w h                           grad q = h grad w - w n
 * and F - o = (x - o) + sum q n / sum w, o the sample itself. The sums, with gradients expanded:
 *   D = sum w,  G = sum grad w,  S = sum q n,  M = sum n (grad q)^T   (3 by 3)
 * d(sum w (Pi - o))/dx = D I + (x - o) G^T + M: the D I term (sum w times dx/dx) comes out of the
 * loop, and F's Jacobian follows by one dual division at the end (pnf_finish_F). */
#ifndef PNF_FILTER_H
#define PNF_FILTER_H

#include "pnf_common.h"

PNF_FN pnf_coeffs pnf_make_coeffs(pnf_real sigma_f, pnf_real sigma_g) {
  pnf_coeffs c;
  c.inv_two_sigma_f2 = (pnf_real)1 / (2 * sigma_f * sigma_f);
  c.inv_two_sigma_g2 = (pnf_real)1 / (2 * sigma_g * sigma_g);
  return c;
}

/* The running sums of the header comment, per lane. */
typedef struct {
  pnf_lane w;                                           /* D */
  pnf_lane gx, gy, gz;                                  /* G */
  pnf_lane sx, sy, sz;                                  /* S */
  pnf_lane mxx, mxy, mxz, myx, myy, myz, mzx, mzy, mzz; /* M, row i = n_i, column k = d/dx_k */
} pnf_sums;

PNF_FN pnf_sums pnf_sums_zero(void) {
  pnf_sums a;
  a.w = 0;
  a.gx = 0;
  a.gy = 0;
  a.gz = 0;
  a.sx = 0;
  a.sy = 0;
  a.sz = 0;
  a.mxx = 0;
  a.mxy = 0;
  a.mxz = 0;
  a.myx = 0;
  a.myy = 0;
  a.myz = 0;
  a.mzx = 0;
  a.mzy = 0;
  a.mzz = 0;
  return a;
}

/* Adds PNF_LANES neighbours to the sums: d = p - x and their normals n, lane by lane. A lane
 * whose exponent is below `cut` adds nothing (PNF_WEIGHT_CUT_EXPONENT; 1 for a padding lane,
 * as every exponent is <= 0). */
PNF_FN void pnf_accumulate(pnf_sums* acc, pnf_lane dx, pnf_lane dy, pnf_lane dz, pnf_lane nx, pnf_lane ny, pnf_lane nz,
                           pnf_lane cut, pnf_coeffs c) {
  pnf_lane dist2 = dx * dx + dy * dy + dz * dz;
  pnf_lane h = dx * nx + dy * ny + dz * nz;
  pnf_lane gh = (pnf_lane)c.inv_two_sigma_g2 * h;
  pnf_sdual e =
      pnf_sdual_make(-((pnf_lane)c.inv_two_sigma_f2 * dist2 + gh * h), (pnf_lane)(2 * c.inv_two_sigma_f2), gh + gh);
  pnf_sdual w = pnf_sdual_exp_cut(e, cut);
  pnf_sdual q = pnf_sdual_mul_h(w, h);
  acc->w += w.v;
  acc->gx += w.a * dx + w.b * nx;
  acc->gy += w.a * dy + w.b * ny;
  acc->gz += w.a * dz + w.b * nz;
  acc->sx += q.v * nx;
  acc->sy += q.v * ny;
  acc->sz += q.v * nz;
  /* grad q, expanded once, then n (grad q)^T */
  pnf_lane ux = q.a * dx + q.b * nx;
  pnf_lane uy = q.a * dy + q.b * ny;
  pnf_lane uz = q.a * dz + q.b * nz;
  acc->mxx += nx * ux;
  acc->mxy += nx * uy;
  acc->mxz += nx * uz;
  acc->myx += ny * ux;
  acc->myy += ny * uy;
  acc->myz += ny * uz;
  acc->mzx += nz * ux;
  acc->mzy += nz * uy;
  acc->mzz += nz * uz;
}

/* A step's neighbours built lane by lane (the reference, GPUs, the partial last step): d = p - q
 * and n per lane, as pnf_accumulate takes them. */
typedef struct {
  pnf_real dx[PNF_LANES], dy[PNF_LANES], dz[PNF_LANES];
  pnf_real nx[PNF_LANES], ny[PNF_LANES], nz[PNF_LANES];
} pnf_lane_rows;

PNF_FN void pnf_set_lane(pnf_lane_rows* r, int k, pnf_real4 p, pnf_real4 n, pnf_real qx, pnf_real qy, pnf_real qz) {
  r->dx[k] = p.x - qx;
  r->dy[k] = p.y - qy;
  r->dz[k] = p.z - qz;
  r->nx[k] = n.x;
  r->ny[k] = n.y;
  r->nz[k] = n.z;
}

PNF_FN void pnf_accumulate_rows(pnf_sums* acc, const pnf_lane_rows* r, pnf_lane cut, pnf_coeffs c) {
  pnf_accumulate(acc, pnf_lane_load(r->dx), pnf_lane_load(r->dy), pnf_lane_load(r->dz), pnf_lane_load(r->nx),
                 pnf_lane_load(r->ny), pnf_lane_load(r->nz), cut, c);
}

/* A lane sum's value and the three partials of its gradient, as a dual. */
PNF_FN pnf_dual pnf_dual_of_sums(pnf_lane v, pnf_lane d0, pnf_lane d1, pnf_lane d2) {
  pnf_dual r;
  r.v = pnf_lane_sum(v);
  r.d[0] = pnf_lane_sum(d0);
  r.d[1] = pnf_lane_sum(d1);
  r.d[2] = pnf_lane_sum(d2);
  return r;
}

/* F - o = sum w (Pi - o) / sum w with its Jacobian in the partials, for the query x = o + x_local.
 * sum w (Pi - o) = x_local D + S, whose partial k is D [i == k] + x_local_i G_k + M_ik. */
PNF_FN pnf_dvec3 pnf_finish_F(pnf_sums acc, pnf_vec3 x_local) {
  pnf_dual den = pnf_dual_of_sums(acc.w, acc.gx, acc.gy, acc.gz);
  pnf_dual nx = pnf_dual_of_sums(acc.sx, acc.mxx, acc.mxy, acc.mxz);
  pnf_dual ny = pnf_dual_of_sums(acc.sy, acc.myx, acc.myy, acc.myz);
  pnf_dual nz = pnf_dual_of_sums(acc.sz, acc.mzx, acc.mzy, acc.mzz);
  nx.v += x_local.x * den.v;
  ny.v += x_local.y * den.v;
  nz.v += x_local.z * den.v;
  for (int k = 0; k < 3; ++k) {
    nx.d[k] += x_local.x * den.d[k];
    ny.d[k] += x_local.y * den.d[k];
    nz.d[k] += x_local.z * den.d[k];
  }
  nx.d[0] += den.v;
  ny.d[1] += den.v;
  nz.d[2] += den.v;
  pnf_dvec3 f;
  f.x = pnf_dual_div(nx, den);
  f.y = pnf_dual_div(ny, den);
  f.z = pnf_dual_div(nz, den);
  return f;
}

/* F(o + x_local) - o with its Jacobian, o = positions[s], over the neighbour list
 * indices[begin, end), PNF_LANES neighbours a step. Each neighbour is one pnf_real4 load of its
 * position and one of its normal. With PNF_LANES > 1 the last step's missing lanes repeat s and
 * are cut (weight 0). Working relative to o keeps float32 precise far from the cloud's centre:
 * p - o is exact for nearby floats, and F - o is of the size of the neighbourhood. */
PNF_FN pnf_dvec3 pnf_eval_F(pnf_vec3 x_local, pnf_index s, PNF_GLOBAL const pnf_index* indices, pnf_offset begin,
                            pnf_offset end, PNF_GLOBAL const pnf_real4* positions, PNF_GLOBAL const pnf_real4* normals,
                            pnf_coeffs c) {
  pnf_real4 o = positions[s];
  const pnf_real qx = o.x + x_local.x, qy = o.y + x_local.y, qz = o.z + x_local.z;
  pnf_sums acc = pnf_sums_zero();
  const pnf_offset full = begin + (end - begin) / PNF_LANES * PNF_LANES;
  pnf_lane_rows rows;
  for (pnf_offset e = begin; e < full; e += PNF_LANES) {
#if PNF_ROW_GATHER
    pnf_lane px, py, pz, vx, vy, vz;
    pnf_gather_step(positions, indices + e, &px, &py, &pz);
    pnf_gather_step(normals, indices + e, &vx, &vy, &vz);
    pnf_accumulate(&acc, px - qx, py - qy, pz - qz, vx, vy, vz, (pnf_lane)(PNF_WEIGHT_CUT_EXPONENT), c);
#else
    for (int k = 0; k < PNF_LANES; ++k) {
      const pnf_index j = indices[e + k];
      pnf_set_lane(&rows, k, positions[j], normals[j], qx, qy, qz);
    }
    pnf_accumulate_rows(&acc, &rows, (pnf_lane)(PNF_WEIGHT_CUT_EXPONENT), c);
#endif
  }
#if PNF_LANES > 1
  if (full < end) {
    pnf_real cut[PNF_LANES];
    for (int k = 0; k < PNF_LANES; ++k) {
      const int real = full + k < end;
      const pnf_index j = real ? indices[full + k] : s;
      pnf_set_lane(&rows, k, positions[j], normals[j], qx, qy, qz);
      cut[k] = real ? (pnf_real)(PNF_WEIGHT_CUT_EXPONENT) : (pnf_real)1;
    }
    pnf_accumulate_rows(&acc, &rows, pnf_lane_load(cut), c);
  }
#endif
  return pnf_finish_F(acc, x_local);
}

/* Column k of J = dF/dx. */
PNF_FN pnf_vec3 pnf_jacobian_column(pnf_dvec3 f, int k) { return pnf_make_vec3(f.x.d[k], f.y.d[k], f.z.d[k]); }

/* n' = C n_s / |C n_s| with the flip and degenerate rules of docs/method.md. *kept is set to 1 when J is
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

/* One pass for point s: its new normal from its neighbour list indices[begin, end); *kept as
 * pnf_update_normal sets it. */
PNF_FN pnf_vec3 pnf_filter_point(pnf_index s, PNF_GLOBAL const pnf_index* indices, pnf_offset begin, pnf_offset end,
                                 PNF_GLOBAL const pnf_real4* positions, PNF_GLOBAL const pnf_real4* normals,
                                 pnf_coeffs c, int* kept) {
  pnf_dvec3 f = pnf_eval_F(pnf_make_vec3(0, 0, 0), s, indices, begin, end, positions, normals, c);
  return pnf_update_normal(f, pnf_vec3_of(normals[s]), kept);
}

#endif /* PNF_FILTER_H */
