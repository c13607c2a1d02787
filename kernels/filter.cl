/* filter.cl: one filter pass, one work-item per point of a chunk [chunk_begin, +chunk_count).
 * offsets/indices are the chunk's CSR lists (offsets[0] = 0); normals_in is the previous pass
 * (Jacobi: never updated in place). All math lives in pnf_filter.h, shared with the reference. */
#include "pnf_filter.h"

__kernel void pnf_filter_pass(__global const float* positions, __global const float* normals_in,
                              __global float* normals_out, __global const ulong* offsets,
                              __global const uint* indices, uint chunk_begin, uint chunk_count,
                              float inv_two_sigma_f2, float inv_two_sigma_g2) {
  uint local_index = get_global_id(0);
  if (local_index >= chunk_count) return;
  uint s = chunk_begin + local_index;
  pnf_coeffs c;
  c.inv_two_sigma_f2 = inv_two_sigma_f2;
  c.inv_two_sigma_g2 = inv_two_sigma_g2;
  pnf_vec3 n = pnf_filter_point(s, indices, offsets[local_index], offsets[local_index + 1], positions,
                                normals_in, c);
  normals_out[3 * (ulong)s] = n.x;
  normals_out[3 * (ulong)s + 1] = n.y;
  normals_out[3 * (ulong)s + 2] = n.z;
}
