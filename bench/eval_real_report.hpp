// pnf_eval_real's cases and how they are reported: markdown tables on stdout and, with --json, every
// case with its grid (eval_real.cpp runs them).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "real_meshes.hpp"

namespace pnf::eval {

// "auto / best" is shown only where the best is above this RMS (degrees): below it (the exact
// input) the ratio is 0/0 or noise.
constexpr double kTinyError = 0.05;
// "No worse than the input" up to this many degrees: the filter stores normals as float, so even
// a run that keeps them moves the angles by about 1e-6 degrees.
constexpr double kSameAsInputDeg = 1e-3;
// The target: --auto within 10% of the grid's best.
constexpr double kWithinOfBest = 1.10;

struct Setting {
  double sigma_f = 0, sigma_g = 0;  // mean radii
  int passes = 0;                   // 0: the input normals
  AngleError error;
};

struct Outcome {
  std::string model, family, normals;
  double noise = 0;  // fraction of the diagonal
  AngleError input, paper, automatic;
  Setting best;
  std::vector<Setting> grid;
  std::string rule;
  bool grid_run = false;
  double normals_seconds = 0, paper_seconds = 0, auto_seconds = 0, grid_seconds = 0;
};

struct ModelInfo {
  std::string name, family;
  std::size_t vertices = 0, triangles = 0;
  MeshNormals stats;  // only the counts are kept; none for a point set (triangles 0)
  double read_seconds = 0, sample_seconds = 0;
};

std::string setting_text(const Setting& s);
std::string error_text(const AngleError& e);
// Auto no worse than its input in RMS and mean (up to kSameAsInputDeg).
bool not_worse(const AngleError& a, const AngleError& input);

// What every report starts with.
struct ReportHeading {
  std::string description, commit;
  std::size_t points = 0;
  std::uint64_t seed = 0;
  bool grid = false;
};
void print_report(const ReportHeading& h, const std::vector<Outcome>& outcomes, const std::vector<ModelInfo>& infos);
void write_json(const std::string& path, const ReportHeading& h, const std::vector<Outcome>& outcomes,
                const std::vector<ModelInfo>& infos);

}  // namespace pnf::eval
