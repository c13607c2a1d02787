// --auto's cross-validation: for input normals whose errors are independent of the positions and
// of each other, the filter setting that best predicts normals it was not shown.
#pragma once

#include <cstddef>
#include <string>

#include "pnf/cloud_view.hpp"
#include "pnf/filter_params.hpp"
#include "pnf/normal_filter.hpp"
#include "pnf/progress.hpp"

namespace pnf::detail {

struct CrossValidation {
  FilterParams params;  // the chosen setting: units radius, the given mean radius; stop rule off
  // Its score (HeldOutPasses::score in the source): about the input normals' mean squared error
  // (sin^2 of the angle) plus the chosen setting's, so an upper estimate of the input's.
  double score = 0;
  double divergence = 0;     // how much of its own input normal a held-out point keeps (0 to 2)
  std::size_t held_out = 0;  // points scored, over all folds
  std::size_t folds = 0;     // disjoint held-out sets, each an eighth of the cloud
  std::size_t settings = 0;
};

// An eighth of the points (at most 50000) is held out; the filter runs on the others
// at every setting of the grid below, and the held-out points follow the same passes, each seeing
// its own normal and the others' but never another held-out one. Where the input normals' errors
// are independent of each other, how far the held-out points' normals end from their own input
// normals, against how much of that input they keep, ranks the settings as their true errors
// would (Stein's unbiased risk estimate, the input's error eliminated: see the source), without
// knowing the truth or the size of the input's error.
// Grid (bench/eval_auto.cpp's): sigma_f 2, 4, 8 and sigma_g 0.25, 0.5, 1, 2, off mean radii; 1, 2,
// 4, 8 passes. Needs cross_validation_min_points() points with normals; progress is told the share
// of settings done (ProgressStage::cross_validation) and may cancel (pnf::Error(cancelled)).
CrossValidation cross_validate(const CloudView& cloud, double mean_radius, NormalFilter& filter,
                               const ProgressCallback& progress = {});

// The fewest points cross_validate takes.
std::size_t cross_validation_min_points();

}  // namespace pnf::detail
