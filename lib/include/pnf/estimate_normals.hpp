// pnf::estimate_normals — unit normals for a point set that has none (PCA fit plus orientation).
#pragma once

#include <string>
#include <vector>

#include "pnf/cloud_view.hpp"
#include "pnf/point_cloud.hpp"
#include "pnf/progress.hpp"

namespace pnf {

// How estimate_normals chooses the sign of each normal. A PCA fit gives a line, not a direction;
// the filter needs consistently oriented normals, so every mode below fixes the sign.
enum class Orientation {
  // n · (viewpoint − p) >= 0: each normal faces the viewpoint. Right for a single scan taken
  // from a known sensor position; wrong for closed models seen from several sides.
  viewpoint,
  // n · (p − c) >= 0, c the centroid (mean position) of the whole cloud: each normal points away
  // from the centre. Right for star-shaped closed surfaces (a sphere, a head); wrong on concave
  // parts (the inside of a cup, the hole of a torus).
  outward,
  // Hoppe et al. 1992 ("Surface reconstruction from unorganized points", §3.3): a minimum
  // spanning tree over the symmetric k-nearest-neighbour graph with edge weight 1 − |n_i · n_j|,
  // traversed from a seed, flipping each child whose normal disagrees with its parent's
  // (n_child · n_parent < 0). Each connected component of the graph (Hoppe adds Euclidean MST
  // edges to join them; pnf orients each on its own) is seeded at its point with the largest z
  // (ties broken deterministically), whose normal is made to point to +z (kept as is when its z
  // component is exactly 0). On a closed surface that point's true normal is +z, so the whole
  // component comes out pointing outward; on an open sheet (terrain) it points up. Works on
  // concave shapes and across sharp edges (a cube); can fail where two sheets are closer than
  // the neighbour spacing, since the graph then joins them.
  mst,
};

// Returns "viewpoint", "outward" or "mst".
const char* to_string(Orientation orientation);

// Parses the names that to_string returns (exact, lower case). Throws Error with
// ErrorCode::invalid_argument naming the text and listing the accepted names.
Orientation parse_orientation(const std::string& name);

// Tunables of estimate_normals. Defaults are the in-class initialisers below.
struct EstimateParams {
  // Number of points in each PCA fit, the point itself included, as PCL's NormalEstimation
  // (setKSearch, `pcl_normal_estimation -k`) and Open3D's KDTreeSearchParamKNN count them: the
  // fit uses the point and its k − 1 nearest other points, which are also its edges in the mst
  // graph. (Before issue 32 pnf counted the other points only: its old k = 16 is today's 17.)
  // Range: k >= 3; there is no upper limit, but a k larger than N is clamped to N (every point).
  // Larger k smooths more and averages out more noise; smaller k keeps sharper features.
  // Default 16.
  int k = 16;
  // How the sign of each normal is chosen; see Orientation. Default mst.
  Orientation orientation = Orientation::mst;
  // Sensor position in model units, used only by Orientation::viewpoint; must be finite.
  // Default the origin.
  Vec3 viewpoint = {0.0, 0.0, 0.0};

  // Throws Error with ErrorCode::invalid_argument naming the first bad field and its value:
  // k < 3, an orientation outside the enum, or a non-finite viewpoint coordinate.
  void validate() const;
};

// Estimates one oriented unit normal per point.
//
// positions:   N points in model units (N by 3, float or double, any stride), N >= 3, every
//              coordinate finite. Read in place; float values widen exactly, so a float view
//              gives the normals of the same values as doubles, bit for bit.
// normals_out: N rows (float or double, any stride) that receive the N unit normals (Euclidean
//              length 1 up to rounding; rounded to float for a float view); row i belongs to
//              positions[i]. Must not overlap positions. Written only after every check passed.
//
// Each normal is the eigenvector of the smallest eigenvalue of the covariance of point i and
// its k − 1 nearest other points (k points in all; Euclidean distance; ties broken by the
// kd-tree, deterministically) about their centroid, i.e. the normal of their total-least-squares
// plane. Its sign is then set as params.orientation says. Where the neighbourhood is degenerate
// (all k points coincident) the normal is +z; where it is a line, it is some unit vector perpendicular to the
// line. Neither case produces NaN. Duplicate points are allowed.
//
// Throws Error: ErrorCode::invalid_argument from params.validate() or when normals_out does not
// have N rows; ErrorCode::invalid_input when N < 3, N > 2^31 − 1, or a coordinate is NaN or
// infinite (the message names the first such vertex index).
//
// Cost: O(N k log N) time for the kd-tree search and the fits; Orientation::mst adds a sort of
// the ~N k graph edges. Memory beyond the input: about (120 + 4 k) N bytes, and about 7 k N
// bytes more with Orientation::mst. For scale, 400k points with k = 16 and mst take about 2 s on
// 2 cores and 120 MB.
//
// Thread safety: reentrant; concurrent calls on different or the same (const) data are safe. The
// per-point work runs on OpenMP threads (omp_get_max_threads()), and the result is bit-for-bit
// the same for any number of threads.
//
// Progress: `progress`, when given, is called on the calling thread about every 0.2 s and at the
// end of each stage, with stage lists (the k-nearest search) then estimate (the fits and the
// orientation), fraction the share of that stage done, passes 0. Returning false cancels: the
// call throws Error(ErrorCode::cancelled) and normals_out is left unchanged.
void estimate_normals(const Vec3ArrayView& positions, MutableVec3ArrayView normals_out,
                      const EstimateParams& params = EstimateParams{}, const ProgressCallback& progress = {});

// The same, returning the normals: estimate_normals(positions, normals, params, progress) into a
// new vector.
std::vector<Vec3> estimate_normals(const std::vector<Vec3>& positions, const EstimateParams& params = EstimateParams{},
                                   const ProgressCallback& progress = {});

// The same, and the surface variation of each fit in `curvature_out` (resized to N; row i
// belongs to positions[i]): lambda0 / (lambda0 + lambda1 + lambda2), the smallest eigenvalue of
// the fit's covariance over their sum, as PCL's NormalEstimation writes it into its `curvature`
// field (Pauly, Gross, Kobbelt 2002). Dimensionless, 0 on a plane, at most 1/3 (isotropic
// spread); 0 where all k points coincide, as in PCL.
std::vector<Vec3> estimate_normals(const std::vector<Vec3>& positions, std::vector<double>& curvature_out,
                                   const EstimateParams& params = EstimateParams{},
                                   const ProgressCallback& progress = {});

}  // namespace pnf
