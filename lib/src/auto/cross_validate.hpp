// --auto's cross-validation: for input normals whose errors are independent of the positions and
// of each other, the filter setting that best predicts normals it was not shown.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "pnf/auto_params.hpp"
#include "pnf/cloud_view.hpp"
#include "pnf/filter_params.hpp"
#include "pnf/normal_filter.hpp"
#include "pnf/progress.hpp"

namespace pnf::detail {

struct CrossValidation {
  FilterParams params;  // the chosen setting: units radius, the given mean radius; stop rule off
  // Its estimated mean squared error (|n - truth|^2, about the angle squared in radians), and
  // the input normals' (input_error_variance) it was estimated with.
  double score = 0;
  double input_error = 0;
  double measured_input_error = 0;  // input_error_variance of the samples (NaN without one)
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
// position_noise (per axis, model units: DataEstimate::position_noise, >= 0) corrects the measured
// input error for the tilt that noisy positions give curved faces' normals (see the source).
// Grid (setting_grid.hpp, pnf_eval_auto's too): sigma_f 2, 4, 8 and sigma_g 0.25, 0.5, 1, 2, off
// mean radii; 1, 2, 4, 8 passes. Needs cross_validation_min_points() points with normals; progress is told the share
// of settings done (ProgressStage::cross_validation) and may cancel (pnf::Error(cancelled)).
CrossValidation cross_validate(const CloudView& cloud, double mean_radius, double position_noise,
                               NormalFilter& filter, const ProgressCallback& progress = {});

// The fewest points cross_validate takes.
std::size_t cross_validation_min_points();

// `choice` with the cross-validated setting (its stop rule kept), cross_validated set, and the
// rule text saying so (the rule's own line kept in rule_before_cross_validation).
AutoChoice with_cross_validation(const AutoChoice& choice, const CrossValidation& cv);

// The parts cross_validate is made of, for a distributed run (lib/src/mpi) to do the same on
// every rank's share of the cloud.

// Which points are held out of a cloud of n points: fold f holds ids[f * held, (f + 1) * held),
// the first few thousand of each fold (in this order) nudged for the divergence.
struct HeldOutDraw {
  std::size_t held = 0, folds = 0;
  std::vector<std::uint32_t> ids;
};
HeldOutDraw draw_held_out(std::size_t n);
// How many of a fold's first points are nudged.
std::size_t nudged_per_fold();
// The rest's filter runs per fold (one per (sigma_f, sigma_g)).
std::size_t rest_runs_per_fold();
// The widest reach of the grid's settings, in mean radii: the others a held-out point may see.
double widest_reach_in_mean_radii();

// One fold as one process holds it.
struct FoldRows {
  std::vector<Vec3> held_positions, held_normals;  // its held-out points, the `nudged` first
  std::size_t nudged = 0;
  // The others: every one within the widest reach of a held-out point must be here (a distributed
  // run's halo after its own).
  std::vector<Vec3> rest_positions, rest_normals;
  Vec3 centre = {0, 0, 0};  // subtracted from every position (the cloud's bounding-box centre)
  // The positions' noise per axis in model units (DataEstimate::position_noise), for the error
  // samples (their tilt of curved faces' normals is not the input normals' error).
  double position_noise = 0;
};

// One setting's sums over the held-out points (all doubles, so that processes can add them up).
struct Tally {
  double distance2 = 0;   // |out - input|^2
  double divergence = 0;  // over the nudged points
  double points = 0, nudged = 0;
  // The setting's mean squared error estimated with the input normals' mean squared error s2.
  double estimated_error(double s2) const;
};
std::vector<Tally> empty_tallies();

// Runs the filter on the fold's rest at `params` (7 passes, stop rule off), calling after_pass
// after every pass with the new normals of all of FoldRows::rest_positions (N by 3, their order).
using RestPassObserver = std::function<void(int pass, const std::vector<double>& rest_normals)>;
using RestRun = std::function<void(const FilterParams& params, const RestPassObserver& after_pass,
                                   const ProgressCallback& still_wanted)>;

// Adds one fold's scores at every setting to `tallies` and one sample of the input normals'
// error per nudged held-out point to `error_samples`; `runs` counts the rest's runs done of
// `all_runs`, for progress.
void score_fold(const FoldRows& fold, double mean_radius, const RestRun& run_rest, const ProgressCallback& progress,
                std::vector<Tally>& tallies, std::vector<double>& error_samples, std::size_t& runs,
                std::size_t all_runs);

// The input normals' mean squared error from all folds' error samples (NaN without one).
double input_error_variance(const std::vector<double>& samples);

// The setting of the lowest estimated error.
CrossValidation best_setting(const std::vector<Tally>& tallies, const HeldOutDraw& draw, double mean_radius,
                             double input_error);

}  // namespace pnf::detail
