// Internal to --auto: normals checked against planes fitted to points they were not made from.
// On noisy positions the surface judge's fits share the positions' noise with normals made from
// them, and its frame follows the normal judged; where it keeps the input, this second check
// splits the points in two by a hash of their coordinates. At samples of one half, the reference
// is the plane (the covariance's least axis) of the nearest kHeldOutPlanePoints points of the
// other half, oriented as those points' input normals; the score of normals n is the mean of
// 1 - n . f over the samples. Where the reference errs independently of n, that mean is, in
// expectation, an increasing affine function of the mean of 1 - cos(error) of n, whatever the
// reference's own noise, so the order of two normal fields is the order of their true errors,
// up to the samples' spread, which gain_z measures. Its bias is the plane's own at edges and
// curved detail: a wider plane rewards smoothing, so the plane is as small as a plane fit can
// usefully be; it then shares points with a PCA input normal's own neighbourhood, which makes the
// input read better than it is and the check keep it more often, not less (docs/auto.md, "The
// held-out check on noisy positions").
#pragma once

#include <cstddef>
#include <vector>

#include "pnf/cloud_view.hpp"

namespace pnf::detail {

// The reference plane's points: the half of the nearest 16 of the whole cloud that lie in the
// other half, the neighbourhood of a 16-point PCA normal (with 16 of the other half the
// reference rewarded smoothing: the kitten at 0.25% noise, PCA-16, 5.70 deg in, 6.12 out).
constexpr int kHeldOutPlanePoints = 8;
// At most this many samples: their score's spread is what gain_z measures.
constexpr std::size_t kHeldOutMaxSamples = 8192;
// A pass is kept only where its gain over the input is this many standard errors of the
// samples' mean gain: a one-sided test at 2.5% against chance for each of the up to 22 passes the
// check scores (the rule's setting's, at most 14, and the fallback's setting's, at most 8),
// Bonferroni's bound on the chance that any of them passes by luck: the normal quantile of
// 1 - 0.025 / 22. (At 2 standard errors the oni at 0.25% noise, PCA-16, kept a pass 2.9 standard
// errors out, 0.17 deg worse than its input.)
constexpr double kHeldOutMinGainZ = 3.05;

class HeldOutPlanes {
 public:
  HeldOutPlanes() = default;
  // Over `positions` (N rows) with the input normals `unit_input` (N by 3, unit), which orient
  // the planes and which gain_z is measured from. In parallel.
  HeldOutPlanes(const Vec3ArrayView& positions, const std::vector<double>& unit_input);

  bool empty() const { return samples_.empty(); }
  std::size_t size() const { return samples_.size(); }
  struct Score {
    // acos(1 - the mean of 1 - n . f) in degrees: the typical angle from the reference planes.
    double disagreement_deg = 0;
    // The mean over the samples of (n - input) . f over its standard error: above
    // kHeldOutMinGainZ, n is nearer the planes than the input by more than chance explains.
    double gain_z = 0;
  };
  // The score of `normals` (N by 3, the cloud's order).
  Score score(const double* normals) const;

 private:
  std::vector<std::size_t> samples_;  // rows, in curve order
  std::vector<double> planes_;        // per sample, the reference plane's unit normal
  std::vector<double> input_;         // per sample, the unit input normal
};

}  // namespace pnf::detail
