/* filter.cl: one filter pass, one work-item per point of a chunk [chunk_begin, +chunk_count).
 * offsets/indices are the chunk's CSR lists (offsets[0] = 0); normals_in is the previous pass
 * (Jacobi: never updated in place). All math lives in pnf_filter.h, shared with the reference;
 * this file only maps work-items to points and, with PNF_LANES > 1, gathers neighbours into
 * vectors of PNF_LANES. */
#include "pnf_filter.h"

#if PNF_LANES > 1
#if PNF_LANES == 4
#define PNF_VLOAD(a) vload4(0, a)
#elif PNF_LANES == 8
#define PNF_VLOAD(a) vload8(0, a)
#else
#define PNF_VLOAD(a) vload16(0, a)
#endif

/* F - o over the list indices[begin, end) of point s at origin o, PNF_LANES neighbours a step.
 * The last step's missing lanes repeat s itself with weight 0. */
static pnf_dvec3 pnf_eval_F_lanes(uint s, pnf_vec3 o, __global const uint* indices, ulong begin, ulong end,
                                  __global const float* positions, __global const float* normals, pnf_coeffs c) {
  pnf_dvec3 x_local = pnf_dvec3_seed(pnf_make_vec3(0, 0, 0));
  pnf_sums acc = pnf_sums_zero();
  for (ulong e = begin; e < end; e += PNF_LANES) {
    float px[PNF_LANES], py[PNF_LANES], pz[PNF_LANES], nx[PNF_LANES], ny[PNF_LANES], nz[PNF_LANES];
    float valid[PNF_LANES];
    for (int k = 0; k < PNF_LANES; ++k) {
      int real = e + k < end;
      uint j = real ? indices[e + k] : s;
      px[k] = positions[3 * (ulong)j] - o.x;
      py[k] = positions[3 * (ulong)j + 1] - o.y;
      pz[k] = positions[3 * (ulong)j + 2] - o.z;
      nx[k] = normals[3 * (ulong)j];
      ny[k] = normals[3 * (ulong)j + 1];
      nz[k] = normals[3 * (ulong)j + 2];
      valid[k] = real ? 1.0f : 0.0f;
    }
    pnf_accumulate(&acc, x_local, PNF_VLOAD(px), PNF_VLOAD(py), PNF_VLOAD(pz), PNF_VLOAD(nx), PNF_VLOAD(ny),
                   PNF_VLOAD(nz), PNF_VLOAD(valid), c);
  }
  return pnf_finish_F(acc);
}
#endif

__kernel void pnf_filter_pass(__global const float* positions, __global const float* normals_in,
                              __global float* normals_out, __global const ulong* offsets, __global const uint* indices,
                              uint chunk_begin, uint chunk_count, float inv_two_sigma_f2, float inv_two_sigma_g2,
                              __global uint* degenerate_count) {
  uint local_index = get_global_id(0);
  if (local_index >= chunk_count) return;
  uint s = chunk_begin + local_index;
  pnf_coeffs c;
  c.inv_two_sigma_f2 = inv_two_sigma_f2;
  c.inv_two_sigma_g2 = inv_two_sigma_g2;
  ulong begin = offsets[local_index], end = offsets[local_index + 1];
  int kept;
#if PNF_LANES == 1
  pnf_vec3 n = pnf_filter_point(s, indices, begin, end, positions, normals_in, c, &kept);
#else
  pnf_dvec3 f = pnf_eval_F_lanes(s, pnf_load_vec3(positions, s), indices, begin, end, positions, normals_in, c);
  pnf_vec3 n = pnf_update_normal(f, pnf_load_vec3(normals_in, s), &kept);
#endif
  if (kept) atomic_inc(degenerate_count); /* rare: contention does not matter */
  normals_out[3 * (ulong)s] = n.x;
  normals_out[3 * (ulong)s + 1] = n.y;
  normals_out[3 * (ulong)s + 2] = n.z;
}
