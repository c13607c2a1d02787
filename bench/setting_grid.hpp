// The grid of filter settings that pnf_eval_auto (bench/eval_auto.cpp) and pnf_eval_real search
// for the best fixed setting: one list, so that both evaluations' "best of the grid" is over the
// same settings.
#pragma once

namespace pnf::eval {

// In mean radii; 1e6 is "off" (the feature term accepts every neighbour).
inline constexpr double kGridSigmaF[] = {2, 4, 8};
inline constexpr double kGridSigmaG[] = {0.25, 0.5, 1, 2, 1e6};
// Each (sigma_f, sigma_g) scored after these passes.
inline constexpr int kGridPasses[] = {1, 2, 4, 8};
inline constexpr int kGridMaxPasses = 8;

}  // namespace pnf::eval
