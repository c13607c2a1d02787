/* filter.cl: one filter pass over a slice of a chunk's points, one work-item per point: the
 * kernel runs with a global offset, so get_global_id(0) is the point's index in the chunk, and
 * work-items at or past slice_end (the global size is rounded up to whole work-groups) do
 * nothing; point chunk_begin + that index is the cloud's. offsets/indices are the chunk's CSR
 * lists (offsets[0] = 0); positions and normals are float4
 * per point (x, y, z, unused); normals_in is the previous pass (Jacobi: never updated in place).
 * All math, the neighbour loop included, lives in pnf_filter.h, shared with the reference; this
 * file only maps work-items to points. PNF_LANES (a build option) sets how many neighbours the
 * loop takes per step. */
#include "pnf_filter.h"

__kernel void pnf_filter_pass(__global const float4* positions, __global const float4* normals_in,
                              __global float4* normals_out, __global const ulong* offsets, __global const uint* indices,
                              uint chunk_begin, uint slice_end, float inv_two_sigma_f2, float inv_two_sigma_g2,
                              __global uint* degenerate_count) {
  uint local_index = get_global_id(0);
  if (local_index >= slice_end) return;
  uint s = chunk_begin + local_index;
  pnf_coeffs c;
  c.inv_two_sigma_f2 = inv_two_sigma_f2;
  c.inv_two_sigma_g2 = inv_two_sigma_g2;
  int kept;
  pnf_vec3 n = pnf_filter_point(s, indices, offsets[local_index], offsets[local_index + 1], positions, normals_in, c,
                                &kept);
  if (kept) atomic_inc(degenerate_count); /* rare: contention does not matter */
  normals_out[s] = (float4)(n.x, n.y, n.z, 0.0f);
}
