// Internal to --auto: the input normals' own noise, read from the normals of each sample's
// nearest points rather than from a surface fitted to the positions, for Stein's risk estimate
// (stein_risk.hpp), which needs the variance of errors independent from point to point.
#pragma once

#include <vector>

#include "pnf/cloud_view.hpp"

namespace pnf::detail {

struct SampleNeighbourhoods;

// The RMS angle (degrees) of the input normals' errors, where those are independent from point
// to point: at each sample, the normals of its kNoiseNeighbours nearest points (turned to agree
// with the sample's) are fitted as a linear function of the position in the sample's tangent
// plane; the residuals' variance per degree of freedom is the noise plus what the true normals
// vary by over the position noise (a point displaced along the surface by its noise carries the
// normal of where it came from: the fitted gradient times the noise, taken out, and what that
// takes out of the noise itself through the gradient's own noise divided back; samples where
// that leaves under half are left out). The median over the samples, for a Gaussian. Errors
// correlated between neighbours (PCA's) read low. -1 without normals, or where under half the
// samples could be fitted (position noise wide against the neighbourhoods: the samples left are
// those the noise happens to leave narrow, and read the surface's variation as no noise).
// `nearest`: each sample's nearest points, nearest first (more than kNoiseNeighbours);
// `position_noise`: per axis, model units.
double neighbour_normal_noise_deg(const std::vector<double>& centred, const CloudView& cloud,
                                  const SampleNeighbourhoods& nearest, double position_noise);

// The points of each sample's fit, the sample included.
constexpr int kNoiseNeighbours = 16;

// The RMS angle (degrees) of the input normals' errors read from chords: for each sample i and
// each of its kChordNeighbours nearest points j, c = (p_j - p_i) . (n_i + n_j) / (2 |p_j - p_i|),
// n_j turned to agree with n_i. A chord meets the two true tangent planes at equal and opposite
// angles, so the surface's curvature cancels to third order in |p_j - p_i|: detail finer than
// the 16 points of neighbour_normal_noise_deg, which that estimate reads as noise (the crank's
// exact normals at 10k points: 21 deg), does not enter. Independent errors of RMS t give c a
// spread of t / 2; twice the median |c| over its Gaussian value (0.6745 SD). Position noise
// enters as the spread of the two points' offsets along the normal over the chord (about
// sqrt(2) sigma / |p_j - p_i|), chords across a crease or between two sheets as outliers the
// median leaves out: it reads high, never low, for independent errors; errors shared by
// neighbours (PCA's) enter whole. -1 without normals or without a chord.
double chord_normal_noise_deg(const std::vector<double>& centred, const CloudView& cloud,
                              const SampleNeighbourhoods& nearest);

// The chords of each sample that chord_normal_noise_deg reads: to its nearest points, where the
// curvature cancels best.
constexpr int kChordNeighbours = 3;

}  // namespace pnf::detail
