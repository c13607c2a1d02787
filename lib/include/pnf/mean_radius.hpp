// pnf::mean_radius, pnf::estimate_mean_radius — the one spacing of pnf: the mean surfel radius
// that radius units, `pnf info`, `pnf filter --auto` and the renderer all use.
#pragma once

#include <cstddef>

#include "pnf/cloud_view.hpp"
#include "pnf/normal_filter.hpp"  // RadiusSource

namespace pnf {

// Estimates the mean surfel radius (the sample spacing) of N points, in model units.
//
// Definition: the points are re-centred on their bounding-box centre and put in Morton order
// (as the filter sees them); for up to 100,000 of them spread evenly along that order (sample s
// is the floor(s N / samples)-th), the mean distance to the 4 nearest other points; the
// estimate is the median of those means. Points whose 4 nearest are all duplicates of
// themselves are left out. On a square grid of spacing h this is exactly h (the 4 nearest are
// the edge neighbours).
//
// Measured (40,000 points in a plane, mean of 5 seeds; tests/mean_radius_test.cpp holds these):
// on a square grid of spacing h jittered uniformly in the plane by up to ±0.1 h per axis 1.00 h,
// ±0.25 h 1.00 h, ±0.5 h 0.94 h (docs/method.md asks for within 25% of h); on uniform random samples of
// density 1 / h² (the square root of the area per point is h) 0.80 h. So on scans and random
// samples the mean radius is about 0.8 of the "area spacing" that --auto measures.
//
// Returns 0 when N < 5 or when every point sits on top of 4 others. The same positions give
// the same value bit for bit in any row order (points that share a Morton cell, 2^-21 of the
// box apart, keep their input order, which can change which of them is sampled).
// Cost: a kd-tree over N points and up to 100,000 searches of 5 neighbours.
// Thread safety: may be called concurrently.
double estimate_mean_radius(const Vec3ArrayView& positions);

// A mean surfel radius and where it came from.
struct MeanRadius {
  double value = 0;  // model units, > 0
  RadiusSource source = RadiusSource::not_used;
};

// The one rule for the mean surfel radius, used by the filter (FilterParams::mean_radius),
// `pnf info` and choose_filter_params:
//   given > 0             -> given (RadiusSource::given);
//   the cloud has radii   -> their mean (RadiusSource::property);
//   else                  -> estimate_mean_radius(cloud.positions) (RadiusSource::estimate).
// Throws pnf::Error(invalid_input) when the estimate is needed and is 0 (fewer than 5 points,
// or most of them at one place). Radii are not validated here (see NormalFilter::run).
// Thread safety: may be called concurrently.
MeanRadius mean_radius(const CloudView& cloud, double given = 0);

}  // namespace pnf
