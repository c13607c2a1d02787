// Internal to --auto: Stein's unbiased risk estimate (SURE) of filtered normals, for input normals
// whose errors are independent from point to point (a scanner's, a mesh's, jittered). With input
// normals y = t + e, e independent with variance s^2 per point (tangent to the sphere), the mean
// squared error of any filter f that is (weakly) differentiable in y is, in expectation,
//
//   |f(y) - t|^2 = |f(y) - y|^2 - s^2 + s^2 div f(y)
//
// per point, div f being the trace of df_i/dy_i over the tangent plane of y_i: no truth needed,
// only the input's noise (DataEstimate::normal_noise_neighbours_deg) and the filter's sensitivity
// to its own input normal, measured by running the filter again with the samples' normals nudged
// (Monte-Carlo divergence: E[b . (f(y + eps b) - f(y))] / eps over random tangent b). The input
// itself scores s^2. Unlike the surface judge, the estimate shares no error with the filter.
// Stein (1981); Ramani, Blu, Unser (2008) for the Monte-Carlo divergence. docs/auto.md.
#pragma once

#include <cstddef>
#include <vector>

#include "pnf/cloud_view.hpp"

namespace pnf::detail {

// Up to this many samples: the estimate subtracts the input's noise from |f(y) - y|^2, both about
// s^2, to find risks a tenth of that; at the surface judge's 4000 samples the sampling error of
// either (about s^2 / sqrt(samples)) reordered passes a few tenths of a degree apart (the casting,
// clean, 10-degree tilts: 3.1 deg after 3 passes, 3.4 after 4, estimated 1.49 and 1.45), at
// every point of 100k it did not (3.06 and 3.32). 24 bytes a sample are kept for each pass.
constexpr std::size_t kSteinMaxSamples = std::size_t(1) << 17;

// The rows Stein's estimate samples: every point of the cloud up to kSteinMaxSamples, else that
// many spread evenly along the Morton curve; in curve order, so that no sum depends on the
// input's row order.
std::vector<std::size_t> stein_samples(const Vec3ArrayView& positions);

class SteinRisk {
 public:
  SteinRisk() = default;
  // At the rows `samples` (stein_samples) of `unit_input` (N by 3), with the input's noise
  // `noise_deg` (RMS).
  SteinRisk(const std::vector<std::size_t>& samples, const std::vector<double>& unit_input, double noise_deg);

  bool empty() const { return samples_.empty(); }
  const std::vector<std::size_t>& samples() const { return samples_; }
  // Per sample, the probe's direction (x y z); probed adds kSteinProbeStep times it.
  const std::vector<double>& probes() const { return probes_; }
  // The input normals (N by 3, unit) with the samples' nudged by the probe: what the second run filters.
  std::vector<double> probed(const std::vector<double>& unit_input) const;
  // The samples' rows of `normals` (N by 3), each made unit: what risk_deg takes from each run.
  std::vector<double> at_samples(const double* normals) const;
  // The estimated RMS error (degrees) of a pass whose normals at the samples are `filtered`, given
  // the same pass of the probed run, `probed_filtered` (both from at_samples). The estimate of the
  // squared error may fall below 0 where a pass removes nearly all the noise (its own error, a
  // few hundredths of the noise squared, is then larger than the risk): then minus the root of
  // its size, so that the order of the passes stays the estimate's.
  double risk_deg(const std::vector<double>& filtered, const std::vector<double>& probed_filtered) const;
  // The input's own: its noise.
  double input_risk_deg() const { return noise_deg_; }

 private:
  std::vector<std::size_t> samples_;
  std::vector<double> input_;   // per sample, its unit input normal
  std::vector<double> probes_;  // per sample, a tangent direction (Rademacher signs projected)
  double noise_deg_ = 0;
};

// The probe's step: the filter runs in float (7 digits); a nudge of 1e-3 moves a normal's own
// output by 1e-5 or more (a pass weighs a point's own normal at least about 1/100), two digits
// above the rounding, while staying where the filter is linear (its feature weights change over
// sigma_g, tens of degrees of the normals).
constexpr double kSteinProbeStep = 1e-3;

}  // namespace pnf::detail
