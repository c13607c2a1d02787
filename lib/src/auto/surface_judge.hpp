// Internal to --auto: how far a normal field is from the surface its positions carry. At samples
// spread through the cloud, a quadric height field is fitted to the sample's neighbours in the
// frame of the normal being judged, by iteratively reweighted least squares with a narrow
// Gaussian weight on the residual: the fit locks onto the sheet of points that passes nearest
// that normal's tangent plane (one face at a sharp edge, the whole neighbourhood on a smooth
// surface) and its slope at the sample is the normal's error there, at the scale (the whole
// neighbourhood or its nearest quarter; fewer points than the input normals follow) where the
// judge's own error is the smaller. The input normals play no part in the fit, so a normal that
// follows the positions' surface scores low, a blurred one at an edge or a tilted one on a smooth
// face scores high. --auto runs its setting pass by pass and keeps the pass (0: the input) that
// scores lowest (docs/auto.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "pnf/cloud_view.hpp"
#include "pnf/estimate_data.hpp"
#include "pnf/point_cloud.hpp"

namespace pnf::detail {

struct SampleNeighbourhoods;

class SurfaceJudge {
 public:
  SurfaceJudge() = default;
  // Judges at the samples of `neighbourhoods` (sample_neighbourhoods.hpp: spread along the Morton
  // curve, neighbours nearest first, so that the judge does not depend on the input's row order)
  // over `centred` (the cloud's positions in its own order, as the normals judged later come in
  // it); `width` is the weight's width on the residual (model units). A distributed run builds it
  // on rank 0 over the whole cloud (lib/src/mpi/choose_filter_params_mpi.cpp).
  SurfaceJudge(const std::vector<double>& centred, const SampleNeighbourhoods& neighbourhoods, double width);

  bool empty() const { return ids_.empty(); }
  std::size_t size() const { return ids_.size(); }
  int neighbours() const { return neighbours_; }
  // The points of the fits that score (the nearest of each neighbourhood): all `neighbours` at
  // first; choose_scale may take the nearest quarter instead.
  int scored() const { return scored_; }
  // Scores at the scale, of the two (all the neighbours, or their nearest quarter), whose own
  // error (own_error_deg) is the smaller in the frames of `normals_xyz`, the input normals: the
  // larger one averages noise better, the smaller one follows detail finer than the larger one's
  // neighbourhood. Where the input normals follow the plane of 64 or more points (input_support),
  // only scales of at most half that many are weighed, or that half alone: fits over the input's
  // own points share its smoothing and read it low (docs/auto.md). Keeps the input's sums at the
  // scale chosen (input_sums), and whether they are plane fits (plane_fit_count, plane_fits).
  void choose_scale(const double* normals_xyz);
  // The count of nearest points (16, 32, ... up to the neighbourhood) whose plane (their
  // covariance's least axis) the normals `normals_xyz` follow most closely, RMS over the samples:
  // the input's support, 64 for PCA normals over 64 points. 0 where that is the widest plane
  // tried, which is also the nearest to normals truer than any plane.
  int input_support(const double* normals_xyz) const;
  // The input's support that choose_scale kept its fits under; 0 where it did not.
  int under_support() const { return under_support_; }
  // The count k (3 up to the neighbourhood) where the normals `normals_xyz` are, at every sample
  // and to rounding, the planes of the sample's nearest k points (their covariance's least axis):
  // 16 for `pnf estimate`'s PCA normals over 16 points, as for any tool's PCA normals over k
  // nearest points. 0 where they are no count's planes (exact normals, tilted ones).
  int plane_fit_count(const double* normals_xyz) const;
  // The input's plane_fit_count, where choose_scale or measure_plane_fits measured it; 0 where
  // neither did.
  int plane_fits() const { return plane_fits_; }
  // Keeps plane_fit_count of the input normals `normals_xyz` without choosing a scale (on noisy
  // positions, for the held-out check: judged_passes.hpp).
  void measure_plane_fits(const double* normals_xyz) { plane_fits_ = empty() ? 0 : plane_fit_count(normals_xyz); }
  // The scales choose_scale weighs for fits of `neighbours` points, the whole neighbourhood first.
  static std::vector<int> scales_of(int neighbours);
  void score_with(int points) {
    scored_ = points < neighbours_ ? points : neighbours_;
    input_sums_ = Sums{};  // they were at the scale before
  }
  // The RMS over the samples of the angle (degrees) between each sample's normal in `normals_xyz`
  // (N by 3, the cloud's order) and the normal of the surface fitted in its frame.
  double rms_deg(const double* normals_xyz) const;
  // The judge's own error (degrees, RMS over the samples), in the frames of `normals_xyz`: the
  // noise of its fits (the slope's standard error from the weighted residuals), and the bias that
  // shows as the fits moving between this scale and the next one down (the nearest quarter of
  // each neighbourhood) by more than both fits' noise explains: detail finer than the
  // neighbourhood, or a sheet the weights cannot hold on to (typical of the samples: a median).
  double own_error_deg(const double* normals_xyz) const;
  struct Sums {
    std::size_t samples = 0;
    double squared = 0;       // the judged angles squared (radians^2), summed over the samples
    double disagreement = 0;  // the two scales' fits apart, squared: the samples' median / ln 2, times their count
    double variance = 0, inner_variance = 0;  // the slopes' variances at the two scales, summed
    double own_error_squared() const;         // summed over the samples: see own_error_deg
    double rms_deg() const;                   // rms_deg of the normals summed
    double own_error_deg() const;             // own_error_deg in their frames
  };
  Sums sums(const double* normals_xyz) const;
  // The input normals' sums (`input`, N by 3) at the scale scored: those choose_scale kept where
  // it was given them, so that the input is fitted once, else fitted now.
  Sums input_sums(const double* input) const { return input_sums_.samples > 0 ? input_sums_ : sums(input); }
  // Fits the input (`input`, N by 3) now and keeps its sums for input_sums, where they are needed
  // before the passes as well as by them (a distributed run's rank 0: judged_passes.hpp,
  // judge_error_deg), so that it is fitted once.
  void keep_input_sums(const double* input) { input_sums_ = input_sums(input); }
  double input_rms_deg(const double* input) const {
    return input_sums_.samples > 0 ? input_sums_.rms_deg() : rms_deg(input);
  }
  static bool quarter_is_better(const Sums& whole, const Sums& quarter);

 private:
  // The sum over the samples of the judged angle squared (radians^2).
  double sum_squared(const double* normals_xyz) const;

  std::vector<std::size_t> ids_;
  std::vector<double> offsets_;  // per sample, `neighbours_` rows of x y z from the sample
  int neighbours_ = 0, scored_ = 0;
  double width_ = 0;
  Sums input_sums_;  // choose_scale's or keep_input_sums', at the scale scored; no samples where neither ran
  int under_support_ = 0;
  int plane_fits_ = 0;
};

// The judge's samples, neighbours and width for a cloud of that estimate (estimate_data.cpp, beside
// the fits' constants it derives from).
struct JudgeGeometry {
  std::size_t samples = 0;  // over the whole cloud (samples_at_scale)
  int neighbours = 0;       // the sample included
  double width = 0;         // model units
  // Positions as clean as the fits' floor (the width set by the spacing, not the noise): the
  // judge's fits then hold no noise that filtered normals could share, and choose_scale may
  // score with the nearest quarter (at 0.25% of the fandisk's diagonal it shared the filter's
  // noise and kept a pass worse than the input).
  bool quarter_allowed = false;
};
JudgeGeometry judge_geometry(const DataEstimate& estimate);

// pnf::estimate_data, also making `judge` (when not null) with judge_geometry's settings, from the
// neighbourhoods of the estimate's own samples where a scale coincides. `poll` is asked, on the
// calling thread, before and about every 0.1 s during each scale's neighbour search, with a share
// of the work done; when it returns false the search stops and pnf::Error(cancelled) is thrown.
DataEstimate estimate_data(const CloudView& cloud, SurfaceJudge* judge,
                           const std::function<bool(double fraction)>& poll = {});

}  // namespace pnf::detail
