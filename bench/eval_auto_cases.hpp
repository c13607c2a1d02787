// pnf_eval_auto's cases and how one is evaluated: the grid's settings (or a cached grid), the
// paper's and the Gaussian setting, and the whole --auto run (eval_auto.cpp reports them).
#pragma once

#include <string>
#include <vector>

#include "pnf/improve_normals_auto.hpp"
#include "pnf/normal_filter.hpp"
#include "setting_grid.hpp"  // the grid is pnf_eval_real's too

namespace pnf::eval {

// The paper's face-model setting: FilterParams' defaults.
inline const FilterParams kPaper{};

// One evaluated cloud: noisy positions, PCA input normals, truth.
struct Case {
  std::string name, family;  // family: "synthetic" or "fandisk"
  std::string noise_label;
  int pca_neighbours = 0;
  PointCloud cloud;
  std::vector<Vec3> truth;
  double true_spacing = 0, true_noise = 0;  // model units (synthetic: sqrt(area / N))
};

struct Setting {
  double sigma_f = 0, sigma_g = 0;
  int passes = 0;
  double rms = 0;
};

struct Outcome {
  double input_rms = 0, paper_rms = 0, gaussian_rms = 0, auto_rms = 0;
  Setting best;
  std::vector<Setting> grid;
  AutoChoice choice;
  int auto_passes = 0;
  double mean_radius = 0, auto_seconds = 0;
  double estimate_seconds = 0;  // the estimate and the rule, and the cross-validation where it ran
};

// The settings a grid search tries: every sigma_f with every sigma_g, one pass at a time up to the
// largest of `passes`, scored after each pass listed there.
struct Grid {
  std::vector<double> sigma_f, sigma_g;
  std::vector<int> passes;
};
inline const Grid kFullGrid{{std::begin(kGridSigmaF), std::end(kGridSigmaF)},
                            {std::begin(kGridSigmaG), std::end(kGridSigmaG)},
                            {std::begin(kGridPasses), std::end(kGridPasses)}};
// For the held-out cases above --full-grid-points (400k points: one full grid there costs about
// 20 times a 20k one): the sigma_g that the tuned cases' optima used (0.25-2 and off), sigma_f at
// the ends of the full grid, and the passes at 2 and 8 (the full grid's optima on shapes with
// edges were at 4-8 passes, on smooth curved ones at 1-2).
inline const Grid kCoarseGrid{{2, 8}, {0.25, 1, 1e6}, {2, 8}};
// Gaussian averaging: the paper's sigma_f and passes with the feature term off (sigma_g "off").
inline constexpr double kGaussianSigmaG = 1e6;

// The grid of case `name` in a JSON file this program wrote (one case a line), or nothing.
std::vector<Setting> cached_grid(const std::string& path, const std::string& name);

// Case `c` on `filter`: its grid (run when `grid`, unless one of `grid_files` holds it), the
// paper's and the Gaussian setting, and --auto; with `estimate_only`, the rule's choice alone.
Outcome evaluate(NormalFilter& filter, const Case& c, bool grid, const std::vector<std::string>& grid_files,
                 const Grid& spec = kFullGrid, bool estimate_only = false);

}  // namespace pnf::eval
