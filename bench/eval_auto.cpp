// pnf_eval_auto: how `--auto` (pnf/improve_normals_auto.hpp) compares with the paper's settings and with
// the best fixed setting of a coarse grid, on clouds whose true normals are known.
//
// Cases: synthetic shapes (plane, sphere, cube, wedges, cylinder, torus, fold; about 20k points sampled
// uniformly at random over their area) with Gaussian position noise of 0, 0.25 and 0.5 spacings
// per axis and PCA input normals from 16 and 64 neighbours, or the true normals tilted by 4 or 12
// degrees RMS (independent errors, as a scanner's); and the PCPNet fandisk (100k points,
// ../shared/data/fandisk100k.xyz + .normals) with Gaussian noise of 0, 0.125%, 0.6% and 1.2% of
// its bounding-box diagonal and PCA normals from 112 neighbours, as in PCPNet. PCA normals are
// oriented by the true ones (a sign only; the filter needs consistent signs, the score ignores
// them). Score: RMS over the points of the angle between the filtered normal and the true one as
// lines, min(t, 180 - t), in degrees.
//
// Grid: sigma_f in {2, 4, 8}, sigma_g in {0.25, 0.5, 1, 2, off (1e6)}, in pnf's default units
// (mean radii estimated from the noisy cloud), 1, 2, 4 and 8 passes (one pass at a time, scored
// after each). The paper's setting (4, 0.5, 4 passes) is one of its points. Fixed seeds: the
// same table on every run on the same device.
//
// --held-out adds issue 14's family (made before that rule change and not fitted to): single
// creases of 60-150 degrees, a long capped cylinder and a rounded box, at 20k, 100k and 400k points,
// noise 0.1 / 0.25 / 0.5 spacings, PCA-16 or jittered true normals; each also against Gaussian
// averaging (the paper's sigma_f and passes, the feature term off), and above --full-grid-points
// against a coarse grid. --estimate-only prints the estimates and choices without filtering.
//
// "auto" is what `pnf filter --auto` runs: improve_normals_auto, the rule and its judged passes
// (docs/auto.md); auto_seconds is the whole run, the choice included.
//
// Prints a table and a summary against the targets (never worse than the input, within 10% of the
// grid's best), and with --json a file for bench/plot_auto.py and --grid-from.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "eval_auto_cases.hpp"
#include "eval_clouds.hpp"
#include "pnf/improve_normals_auto.hpp"
#include "pnf/mean_radius.hpp"
#include "pnf/normal_filter.hpp"

namespace {

using namespace pnf;
using namespace pnf::eval;

// PCPNet's noise levels, as fractions of the bounding-box diagonal, and its PCA neighbourhood.
constexpr double kFandiskNoise[] = {0, 0.00125, 0.006, 0.012};
constexpr int kFandiskPcaNeighbours = 112;
// The held-out cases' jittered input normals: the true ones tilted by this RMS angle, degrees.
constexpr double kJitterRmsDeg = 8;

std::string setting_text(const Setting& s) { return eval::setting_text(s.sigma_f, s.sigma_g, s.passes); }

std::string auto_text(const Outcome& o) {
  char text[64];
  // In area spacings, the rule's unit (docs/auto.md's tables); the params are in mean radii.
  const FilterParams& p = o.choice.params;
  const double to_area_spacings = p.mean_radius / o.choice.estimate.area_spacing;
  if (p.sigma_g >= 1e5) {
    std::snprintf(text, sizeof text, "%.2g/off/%d", p.sigma_f * to_area_spacings, o.auto_passes);
  } else {
    std::snprintf(text, sizeof text, "%.2g/%.2g/%d", p.sigma_f * to_area_spacings, p.sigma_g * to_area_spacings,
                  o.auto_passes);
  }
  return text;
}

// auto / best, or "-" without a grid or where the best is below kTinyError (0/0 on a clean plane).
constexpr double kTinyError = 0.05;
// The target: --auto within 10% of the grid's best.
constexpr double kWithinOfBest = 1.10;
// "Worse than the input" past this many degrees: a run of 0 passes returns the input normals
// through the filter's float storage, which moves the RMS by about 1e-6 degrees.
constexpr double kSameAsInputDeg = 1e-3;
std::string ratio_text(const Outcome& o, bool no_grid) {
  if (no_grid || o.best.rms < kTinyError) return "-";
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", o.auto_rms / o.best.rms);
  return text;
}

std::string json_escape(const std::string& s) {
  std::string out;
  for (char ch : s) {
    if (ch == '"' || ch == '\\') out += '\\';
    out += ch;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"pnf_eval_auto: --auto against the paper's settings and the best of a grid, on known normals"};
  bool quick = false, no_grid = false, no_synthetic = false, no_fandisk = false;
  std::size_t points = 20000;
  std::string json_path, backend = "opencl", device, data_dir = PNF_SHARED_DATA_DIR;
  std::vector<std::string> shapes = {"plane", "sphere", "cube", "wedges", "cylinder", "torus", "fold"};
  std::vector<double> noises = {0, 0.25, 0.5};
  std::vector<int> pca_ks = {16, 64};
  // Input normals whose errors are independent of the positions (a scanner's, a mesh's): the true
  // ones tilted by these RMS angles. Not the held-out family's 8 degrees, so that the rule's line
  // for such normals is tuned on other cases than those it is judged on.
  std::vector<double> jitters = {4, 12};
  std::vector<int> fandisk_levels = {0, 1, 2, 3};
  std::vector<std::string> grid_files;
  bool held_out = false, estimate_only = false;
  std::vector<std::string> held_out_shapes = {"crease", "longcyl", "roundbox"};
  std::vector<double> angles = {60, 90, 120, 135, 150};
  std::vector<std::size_t> held_out_points = {20000, 100000, 400000};
  std::vector<double> held_out_noises = {0.1, 0.25, 0.5};
  std::vector<std::string> held_out_normals = {"pca16", "jitter"};
  std::size_t full_grid_points = 100000;
  app.add_flag("--quick", quick, "plane, cube and torus at noise 0 and 0.5, PCA-16 only; fandisk levels 0 and 2");
  app.add_flag("--no-grid", no_grid, "skip the grid search (auto and paper only)");
  app.add_flag("--no-synthetic", no_synthetic, "skip the synthetic shapes");
  app.add_flag("--no-fandisk", no_fandisk, "skip fandisk");
  app.add_option("--shapes", shapes, "synthetic shapes to run");
  app.add_option("--noise", noises, "synthetic position noise levels, in spacings (per axis)");
  app.add_option("--pca", pca_ks, "PCA neighbourhood sizes for the synthetic input normals (--pca 0: none)");
  app.add_option("--jitter", jitters,
                 "RMS tilts (degrees) of the synthetic shapes' jittered true normals, a case each (--jitter 0: none)");
  app.add_option("--fandisk-levels", fandisk_levels,
                 "fandisk noise levels to run: 0..3 = 0, 0.125, 0.6, 1.2% of diagonal");
  app.add_option("--points", points, "points per synthetic shape (default 20000)");
  app.add_option("--data", data_dir, "folder with fandisk100k.xyz and fandisk100k.normals");
  app.add_option("--json", json_path, "write every case, the grid included, as JSON");
  app.add_option("--grid-from", grid_files,
                 "JSON files of earlier runs: a case found there (same name, same seeds) reuses its grid instead "
                 "of running it again, so a change of the rule costs only the --auto runs");
  app.add_flag("--held-out", held_out,
               "the held-out family of issue 14 (single creases, a long capped cylinder, a rounded box at 20k-400k "
               "points), after the cases above; with --no-synthetic --no-fandisk only it");
  app.add_flag("--estimate-only", estimate_only, "only the estimates and the rule's choice (no filtering, no grid)");
  app.add_option("--held-out-shapes", held_out_shapes, "crease, longcyl, roundbox");
  app.add_option("--angles", angles, "dihedral angles of the single creases, degrees");
  app.add_option("--held-out-points", held_out_points, "point counts of the held-out shapes");
  app.add_option("--held-out-noise", held_out_noises, "held-out position noise, in spacings (per axis)");
  app.add_option("--held-out-normals", held_out_normals,
                 "held-out input normals: pca16 (PCA over 16 neighbours) and/or jitter (true normals tilted by "
                 "Gaussian angles of 8 degrees RMS)");
  app.add_option("--full-grid-points", full_grid_points,
                 "held-out cases with more points than this get the coarse grid (sigma_f 2, 8; sigma_g 0.25, 1, off; "
                 "2 and 8 passes)");
  app.add_option("--backend", backend, "opencl (default) or reference")->check(CLI::IsMember({"opencl", "reference"}));
  app.add_option("--device", device, "OpenCL device selector");
  CLI11_PARSE(app, argc, argv);
  if (estimate_only) no_grid = true;
  if (quick) {
    shapes = {"plane", "cube", "torus"};
    noises = {0, 0.5};
    pca_ks = {16};
    jitters = {};
    fandisk_levels = {0, 2};
  }

  FilterOptions options;
  options.device = backend == "reference" ? Device::reference() : Device::parse(device);
  NormalFilter filter(options);
  std::printf("pnf_eval_auto on %s\n", filter.device_description().c_str());
  std::printf(
      "RMS angle to the true normals as lines, degrees. Settings: sigma_f/sigma_g/passes; grid and paper in\n"
      "mean radii (pnf default units), auto in estimated spacings. gauss = sigma_f and passes of the paper with the\n"
      "feature term off. ratio = auto / best of grid.\n\n");
  std::printf("%-24s %6s %6s %6s %6s %7s %13s %13s %6s  %s\n", "case", "input", "paper", "gauss", "best", "auto",
              "best setting", "auto setting", "ratio",
              "estimate: spacing/radius, noise in spacings (true), normals deg, features %, curved %, normal error "
              "correlation, crease length per size, normal-position coupling, crease sharpness, normal crease length");

  std::vector<std::pair<Case, Outcome>> results;
  auto report = [&](Case& c, const Outcome& o) {
    const DataEstimate& e = o.choice.estimate;
    std::printf(
        "%-24s %6.2f %6.2f %6.2f %6.2f %7.2f %13s %13s %6s  %.3f, %.2f (%.2f), %.1f, %.0f, %.0f, %.2f, %.2f, %.2f, "
        "%.3f, %.2f\n",
        c.name.c_str(), o.input_rms, o.paper_rms, o.gaussian_rms, no_grid ? 0.0 : o.best.rms, o.auto_rms,
        no_grid ? "-" : setting_text(o.best).c_str(), auto_text(o).c_str(), ratio_text(o, no_grid).c_str(),
        e.area_spacing / o.mean_radius, e.position_noise_area_spacings(), c.true_noise / e.area_spacing,
        e.normal_noise_deg, 100 * e.feature_share, 100 * e.curved_share, e.normal_error_correlation, e.crease_length,
        e.normal_position_coupling, e.crease_sharpness, e.normal_crease_length);
    std::fflush(stdout);
    c.cloud = {};
    c.truth = {};
    results.emplace_back(c, o);
  };

  if (!no_synthetic) {
    // Seeds follow the shape and the noise level, not the order asked for, so a case has the
    // same points in every selection (and --grid-from finds its grid).
    const std::vector<std::string> all_shapes = {"plane", "sphere", "cube", "wedges", "cylinder", "torus", "fold"};
    const std::vector<double> all_noises = {0, 0.25, 0.5};
    for (const std::string& name : shapes) {
      const auto shape_index = std::size_t(std::find(all_shapes.begin(), all_shapes.end(), name) - all_shapes.begin());
      const unsigned shape_seed = 1 + 4 * unsigned(shape_index);
      const Shape shape = make_shape(name, points, shape_seed);
      const double spacing = std::sqrt(shape.area / double(points));
      for (double noise : noises) {
        const auto noise_index =
            std::size_t(std::find(all_noises.begin(), all_noises.end(), noise) - all_noises.begin());
        const unsigned noise_seed = noise_index < all_noises.size() ? shape_seed + 1 + unsigned(noise_index)
                                                                    : shape_seed + 100 + unsigned(noise * 1000);
        std::vector<Vec3> noisy = shape.positions;
        add_noise(noisy, noise * spacing, noise_seed);
        // One case of these positions with `normals` as input, named "<shape> n<noise> <source>".
        auto run_case = [&](const std::string& source, std::vector<Vec3> normals, int pca_neighbours) {
          Case c;
          char label[64];
          std::snprintf(label, sizeof label, "%s n%.2g %s", name.c_str(), noise, source.c_str());
          c.name = label;
          c.family = "synthetic";
          std::snprintf(label, sizeof label, "%.2g", noise);
          c.noise_label = label;
          c.pca_neighbours = pca_neighbours;
          c.cloud.positions = noisy;
          c.cloud.normals = std::move(normals);
          c.truth = shape.normals;
          c.true_spacing = spacing;
          c.true_noise = noise * spacing;
          report(c, evaluate(filter, c, !no_grid, grid_files, kFullGrid, estimate_only));
        };
        for (int k : pca_ks) {
          if (k > 0) run_case("pca" + std::to_string(k), pca_normals(noisy, shape.normals, k), k);
        }
        for (double degrees : jitters) {
          if (!(degrees > 0)) continue;
          char source[32];
          std::snprintf(source, sizeof source, "jitter%g", degrees);
          run_case(source, jittered_normals(shape.normals, degrees, noise_seed + 50 + unsigned(degrees)), 0);
        }
      }
    }
  }

  if (held_out) {
    // Seeds follow the case's parameters, not the order asked for, so a case has the same points
    // in every selection (and --grid-from finds its grid).
    for (const std::string& kind : held_out_shapes) {
      const std::vector<double> kind_angles = kind == "crease" ? angles : std::vector<double>{0};
      for (double angle : kind_angles) {
        for (std::size_t n : held_out_points) {
          const unsigned kind_seed = kind == "longcyl" ? 1 : kind == "roundbox" ? 2 : 0;
          const unsigned shape_seed = 1000 + unsigned(angle) * 7 + unsigned(n / 1000) * 13 + kind_seed;
          Shape shape;
          if (kind == "crease") {
            shape = make_crease(angle, n, shape_seed);
          } else if (kind == "longcyl") {
            shape = make_long_cylinder(n, shape_seed);
          } else if (kind == "roundbox") {
            shape = make_rounded_box(n, shape_seed);
          } else {
            throw std::runtime_error("unknown held-out shape " + kind);
          }
          const double spacing = std::sqrt(shape.area / double(n));
          for (double noise : held_out_noises) {
            std::vector<Vec3> noisy = shape.positions;
            add_noise(noisy, noise * spacing, shape_seed + 1 + unsigned(noise * 1000));
            for (const std::string& normals : held_out_normals) {
              Case c;
              char label[64];
              std::snprintf(label, sizeof label, "%s n%.2g %s %zuk", shape.name.c_str(), noise, normals.c_str(),
                            n / 1000);
              c.name = label;
              c.family = "held-out";
              std::snprintf(label, sizeof label, "%.2g", noise);
              c.noise_label = label;
              c.cloud.positions = noisy;
              if (normals == "pca16") {
                c.pca_neighbours = 16;
                c.cloud.normals = pca_normals(noisy, shape.normals, 16);
              } else if (normals == "jitter") {
                c.cloud.normals = jittered_normals(shape.normals, kJitterRmsDeg, shape_seed + 2);
              } else {
                throw std::runtime_error("unknown held-out normals " + normals);
              }
              c.truth = shape.normals;
              c.true_spacing = spacing;
              c.true_noise = noise * spacing;
              report(c, evaluate(filter, c, !no_grid, grid_files, n > full_grid_points ? kCoarseGrid : kFullGrid,
                                 estimate_only));
            }
          }
        }
      }
    }
  }

  if (!no_fandisk) {
    std::ifstream xyz(data_dir + "/fandisk100k.xyz"), nrm(data_dir + "/fandisk100k.normals");
    if (!xyz || !nrm) {
      std::printf("fandisk: skipped, %s/fandisk100k.xyz or .normals is absent\n", data_dir.c_str());
    } else {
      std::vector<Vec3> positions, truth;
      Vec3 p, n;
      while (xyz >> p[0] >> p[1] >> p[2]) positions.push_back(p);
      while (nrm >> n[0] >> n[1] >> n[2]) truth.push_back(unit(n));
      Vec3 low = positions[0], high = positions[0];
      for (const Vec3& q : positions) {
        for (int a = 0; a < 3; ++a) low[a] = std::min(low[a], q[a]), high[a] = std::max(high[a], q[a]);
      }
      const Vec3 extent = add(high, scale(low, -1));
      const double diagonal = std::sqrt(dot(extent, extent));
      for (int level : fandisk_levels) {
        if (level < 0 || level > 3) continue;
        Case c;
        char label[64];
        std::snprintf(label, sizeof label, "fandisk %.3g%% pca%d", kFandiskNoise[level] * 100, kFandiskPcaNeighbours);
        c.name = label;
        c.family = "fandisk";
        std::snprintf(label, sizeof label, "%.3g%%", kFandiskNoise[level] * 100);
        c.noise_label = label;
        c.pca_neighbours = kFandiskPcaNeighbours;
        c.cloud.positions = positions;
        add_noise(c.cloud.positions, kFandiskNoise[level] * diagonal, 100 + unsigned(level));
        c.cloud.normals = pca_normals(c.cloud.positions, truth, kFandiskPcaNeighbours);
        c.truth = truth;
        c.true_noise = kFandiskNoise[level] * diagonal;
        c.true_spacing = 0;  // unknown (the mesh's area is not at hand): noise shown in estimated spacings
        report(c, evaluate(filter, c, !no_grid, grid_files, kFullGrid, estimate_only));
      }
    }
  }

  // Against the targets: never worse than the input, within 10% of the grid's best.
  if (!estimate_only) {
    int worse = 0, over = 0, graded = 0;
    for (const auto& [c, o] : results) {
      if (o.auto_rms > o.input_rms + kSameAsInputDeg) {
        ++worse;
        std::printf("worse than its input: %s (%.2f against %.2f)\n", c.name.c_str(), o.auto_rms, o.input_rms);
      }
      if (no_grid || o.best.rms < kTinyError) continue;
      ++graded;
      if (o.auto_rms > kWithinOfBest * o.best.rms) {
        ++over;
        std::printf("over 10%% above the grid's best: %s (%.3f)\n", c.name.c_str(), o.auto_rms / o.best.rms);
      }
    }
    std::printf("%zu cases: %d worse than their input; %d of %d with a grid more than 10%% above its best\n",
                results.size(), worse, over, graded);
  }

  if (!json_path.empty()) {
    std::ofstream out(json_path);
    out << "{\n  \"device\": \"" << json_escape(filter.device_description()) << "\",\n  \"cases\": [\n";
    for (std::size_t i = 0; i < results.size(); ++i) {
      const Case& c = results[i].first;
      const Outcome& o = results[i].second;
      const DataEstimate& e = o.choice.estimate;
      out << "    {\"name\": \"" << c.name << "\", \"family\": \"" << c.family << "\", \"noise\": \"" << c.noise_label
          << "\", \"pca\": " << c.pca_neighbours << ", \"input\": " << o.input_rms << ", \"paper\": " << o.paper_rms
          << ", \"gauss\": " << o.gaussian_rms << ", \"auto\": " << o.auto_rms
          << ", \"best\": " << (no_grid ? 0.0 : o.best.rms) << ", \"best_setting\": \""
          << (no_grid ? "" : setting_text(o.best)) << "\", \"auto_setting\": \"" << auto_text(o)
          << "\", \"mean_radius\": " << o.mean_radius << ", \"spacing\": " << e.area_spacing
          << ", \"noise_spacings\": " << e.position_noise_area_spacings() << ", \"true_noise\": " << c.true_noise
          << ", \"normal_noise_deg\": " << e.normal_noise_deg << ", \"feature_share\": " << e.feature_share
          << ", \"curved_share\": " << e.curved_share << ", \"crease_length\": " << e.crease_length
          << ", \"normal_error_correlation\": " << e.normal_error_correlation
          << ", \"normal_position_coupling\": " << e.normal_position_coupling
          << ", \"crease_sharpness\": " << e.crease_sharpness
          << ", \"normal_crease_length\": " << e.normal_crease_length << ", \"choose_seconds\": " << o.estimate_seconds
          << ", \"auto_seconds\": " << o.auto_seconds << ", \"rule\": \"" << json_escape(o.choice.rule)
          << "\", \"judged\": \"" << json_escape(o.choice.judged) << "\", \"grid\": [";
      for (std::size_t g = 0; g < o.grid.size(); ++g) {
        const Setting& s = o.grid[g];
        out << (g ? ", " : "") << "[" << s.sigma_f << ", " << s.sigma_g << ", " << s.passes << ", " << s.rms << "]";
      }
      out << "]}" << (i + 1 < results.size() ? "," : "") << "\n";
    }
    out << "  ]\n}\n";
  }
  return 0;
}
