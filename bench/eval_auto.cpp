// pnf_eval_auto: how `--auto` (pnf/auto_params.hpp) compares with the paper's settings and with
// the best fixed setting of a coarse grid, on clouds whose true normals are known.
//
// Cases: synthetic shapes (plane, sphere, cube, wedges, cylinder, torus; about 20k points sampled
// uniformly at random over their area) with Gaussian position noise of 0, 0.25 and 0.5 spacings
// per axis and PCA input normals from 16 and 64 neighbours; and the PCPNet fandisk (100k points,
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
// Prints a table, and with --json a file for bench/plot_auto.py.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "geometry.hpp"
#include "pnf/auto_params.hpp"
#include "pnf/estimate_normals.hpp"
#include "pnf/mean_radius.hpp"
#include "pnf/normal_filter.hpp"

namespace {

using namespace pnf;

using geometry::kPi;
constexpr double kGridSigmaF[] = {2, 4, 8};
constexpr double kGridSigmaG[] = {0.25, 0.5, 1, 2, 1e6};
constexpr int kGridPasses[] = {1, 2, 4, 8};
constexpr int kMaxGridPasses = 8;
// The paper's face-model setting: FilterParams' defaults.
const FilterParams kPaper{};
// PCPNet's noise levels, as fractions of the bounding-box diagonal, and its PCA neighbourhood.
constexpr double kFandiskNoise[] = {0, 0.00125, 0.006, 0.012};
constexpr int kFandiskPcaNeighbours = 112;

Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3 scale(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3 unit(const Vec3& a) { return scale(a, 1.0 / std::sqrt(dot(a, a))); }

// RMS of the angle between lines, in degrees.
double rms_line_angle(const std::vector<Vec3>& normals, const std::vector<Vec3>& truth) {
  double sum = 0;
  for (std::size_t i = 0; i < normals.size(); ++i) {
    const Vec3 a = unit(normals[i]);
    double t = geometry::angle_degrees(a, truth[i]);
    t = std::min(t, 180 - t);
    sum += t * t;
  }
  return std::sqrt(sum / double(normals.size()));
}

// A surface with known normals: N points uniformly over its area.
struct Shape {
  std::string name;
  std::vector<Vec3> positions, normals;
  double area = 0;
};

// Planar pieces given as a parallelogram: origin + s a + t b, s, t in [0, 1], normal a x b.
struct Patch {
  Vec3 origin, a, b;
};

Shape sample_patches(const std::string& name, const std::vector<Patch>& patches, std::size_t points,
                     std::mt19937& rng) {
  Shape shape;
  shape.name = name;
  std::vector<double> areas;
  for (const Patch& p : patches) {
    const Vec3 c = cross(p.a, p.b);
    areas.push_back(std::sqrt(dot(c, c)));
    shape.area += areas.back();
  }
  std::discrete_distribution<std::size_t> pick(areas.begin(), areas.end());
  std::uniform_real_distribution<double> u01(0, 1);
  for (std::size_t i = 0; i < points; ++i) {
    const Patch& p = patches[pick(rng)];
    shape.positions.push_back(add(p.origin, add(scale(p.a, u01(rng)), scale(p.b, u01(rng)))));
    shape.normals.push_back(unit(cross(p.a, p.b)));
  }
  return shape;
}

// Sampled by rejection from a parameter box: `map` gives position and normal at (s, t) in
// [0, 1]^2, `density` the area element there, at most `max_density`.
template <typename Map, typename Density>
Shape sample_param(const std::string& name, double area, Map map, Density density, double max_density,
                   std::size_t points, std::mt19937& rng) {
  Shape shape;
  shape.name = name;
  shape.area = area;
  std::uniform_real_distribution<double> u01(0, 1);
  while (shape.positions.size() < points) {
    const double s = u01(rng), t = u01(rng);
    if (u01(rng) * max_density > density(s, t)) continue;
    Vec3 p, n;
    map(s, t, p, n);
    shape.positions.push_back(p);
    shape.normals.push_back(n);
  }
  return shape;
}

Shape make_shape(const std::string& name, std::size_t points, unsigned seed) {
  std::mt19937 rng(seed);
  if (name == "plane") return sample_patches(name, {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}, points, rng);
  if (name == "cube") {
    return sample_patches(name,
                          {{{0, 0, 0}, {0, 1, 0}, {1, 0, 0}},
                           {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},
                           {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}},
                           {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},
                           {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}},
                           {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}},
                          points, rng);
  }
  if (name == "wedges") {
    // A profile in x-z extruded along y: a 90-degree ridge, 135-degree creases and a 60-degree
    // valley, so one cloud has dihedral angles from sharp to shallow.
    const std::vector<Vec3> profile = {{0, 0, 0},   {0.3, 0, 0},     {0.6, 0, 0.3},
                                       {0.9, 0, 0}, {1.05, 0, 0.26}, {1.4, 0, 0.26}};
    std::vector<Patch> patches;
    for (std::size_t i = 0; i + 1 < profile.size(); ++i) {
      patches.push_back({profile[i], {0, 1, 0}, add(profile[i + 1], scale(profile[i], -1))});
    }
    return sample_patches(name, patches, points, rng);
  }
  if (name == "sphere") {
    std::normal_distribution<double> g(0, 1);
    Shape shape;
    shape.name = name;
    shape.area = 4 * kPi;
    for (std::size_t i = 0; i < points; ++i) {
      const Vec3 d = unit({g(rng), g(rng), g(rng)});
      shape.positions.push_back(d);
      shape.normals.push_back(d);
    }
    return shape;
  }
  if (name == "cylinder") {
    // Radius 0.5, height 1, closed by two caps: a curved face meeting flat ones at 90 degrees.
    constexpr double r = 0.5, height = 1;
    const double side = 2 * kPi * r * height, cap = kPi * r * r;
    std::uniform_real_distribution<double> u01(0, 1);
    Shape shape;
    shape.name = name;
    shape.area = side + 2 * cap;
    for (std::size_t i = 0; i < points; ++i) {
      const double pick = u01(rng) * shape.area, angle = 2 * kPi * u01(rng);
      if (pick < side) {
        shape.positions.push_back({r * std::cos(angle), r * std::sin(angle), height * u01(rng)});
        shape.normals.push_back({std::cos(angle), std::sin(angle), 0});
      } else {
        const double radius = r * std::sqrt(u01(rng));
        const bool top = pick < side + cap;
        shape.positions.push_back({radius * std::cos(angle), radius * std::sin(angle), top ? height : 0});
        shape.normals.push_back({0, 0, top ? 1.0 : -1.0});
      }
    }
    return shape;
  }
  if (name == "torus") {
    constexpr double big = 1, small = 0.35;
    auto map = [&](double s, double t, Vec3& p, Vec3& n) {
      const double u = 2 * kPi * s, v = 2 * kPi * t;
      n = {std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v)};
      p = {(big + small * std::cos(v)) * std::cos(u), (big + small * std::cos(v)) * std::sin(u), small * std::sin(v)};
    };
    auto density = [&](double, double t) { return big + small * std::cos(2 * kPi * t); };
    return sample_param(name, 4 * kPi * kPi * big * small, map, density, big + small, points, rng);
  }
  throw std::runtime_error("unknown shape " + name);
}

// One evaluated cloud: noisy positions, PCA input normals, truth.
struct Case {
  std::string name, family;  // family: "synthetic" or "fandisk"
  std::string noise_label;
  int pca_neighbours = 0;
  PointCloud cloud;
  std::vector<Vec3> truth;
  double true_spacing = 0, true_noise = 0;  // model units (synthetic: sqrt(area / N))
};

void add_noise(std::vector<Vec3>& positions, double sigma, unsigned seed) {
  if (sigma <= 0) return;
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0, sigma);
  for (Vec3& p : positions) p = {p[0] + g(rng), p[1] + g(rng), p[2] + g(rng)};
}

std::vector<Vec3> pca_normals(const std::vector<Vec3>& positions, const std::vector<Vec3>& truth, int k) {
  EstimateParams params;
  params.k = k;
  params.orientation = Orientation::outward;  // replaced by the true side below
  std::vector<Vec3> normals = estimate_normals(positions, params);
  for (std::size_t i = 0; i < normals.size(); ++i) {
    if (dot(normals[i], truth[i]) < 0) normals[i] = scale(normals[i], -1);
  }
  return normals;
}

struct Setting {
  double sigma_f = 0, sigma_g = 0;
  int passes = 0;
  double rms = 0;
};

struct Outcome {
  double input_rms = 0, paper_rms = 0, auto_rms = 0;
  Setting best;
  std::vector<Setting> grid;
  AutoChoice choice;
  int auto_passes = 0;
  double mean_radius = 0, auto_seconds = 0, estimate_seconds = 0;
};

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// The grid of case `name` in a JSON file this program wrote (one case a line), or nothing.
std::vector<Setting> cached_grid(const std::string& path, const std::string& name) {
  std::ifstream in(path);
  std::string line;
  const std::string key = "{\"name\": \"" + name + "\"";
  while (std::getline(in, line)) {
    if (line.find(key) == std::string::npos) continue;
    std::vector<Setting> grid;
    std::size_t at = line.find("\"grid\": [");
    if (at == std::string::npos) return grid;
    at = line.find('[', at) + 1;
    Setting s;
    char bracket = 0;
    std::istringstream items(line.substr(at));
    while (items >> bracket && bracket == '[') {
      char comma = 0;
      items >> s.sigma_f >> comma >> s.sigma_g >> comma >> s.passes >> comma >> s.rms >> bracket >> comma;
      grid.push_back(s);
    }
    return grid;
  }
  return {};
}

Outcome evaluate(NormalFilter& filter, const Case& c, bool grid, const std::vector<std::string>& grid_files) {
  Outcome o;
  o.input_rms = rms_line_angle(c.cloud.normals, c.truth);
  o.mean_radius = estimate_mean_radius(c.cloud.positions);
  for (const std::string& file : grid_files) {
    if (!grid || !o.grid.empty()) break;
    o.grid = cached_grid(file, c.name);
  }
  if (!o.grid.empty()) {
    o.best.rms = 1e9;
    for (const Setting& s : o.grid) {
      if (s.rms < o.best.rms) o.best = s;
      if (s.sigma_f == kPaper.sigma_f && s.sigma_g == kPaper.sigma_g && s.passes == kPaper.iterations)
        o.paper_rms = s.rms;
    }
  } else if (grid) {
    o.best.rms = 1e9;
    for (double sf : kGridSigmaF) {
      for (double sg : kGridSigmaG) {
        PointCloud step = c.cloud;
        FilterParams params;
        params.sigma_f = sf;
        params.sigma_g = sg;
        params.iterations = 1;
        params.mean_radius = o.mean_radius;
        for (int pass = 1; pass <= kMaxGridPasses; ++pass) {
          step.normals = filter.run(step, params).normals;
          if (std::find(std::begin(kGridPasses), std::end(kGridPasses), pass) == std::end(kGridPasses)) continue;
          Setting s{sf, sg, pass, rms_line_angle(step.normals, c.truth)};
          o.grid.push_back(s);
          if (s.rms < o.best.rms) o.best = s;
          if (sf == kPaper.sigma_f && sg == kPaper.sigma_g && pass == kPaper.iterations) o.paper_rms = s.rms;
        }
      }
    }
  } else {
    FilterParams paper = kPaper;
    paper.mean_radius = o.mean_radius;
    o.paper_rms = rms_line_angle(filter.run(c.cloud, paper).normals, c.truth);
  }
  auto t = std::chrono::steady_clock::now();
  o.choice = choose_filter_params(c.cloud);
  o.estimate_seconds = seconds_since(t);
  t = std::chrono::steady_clock::now();
  FilterResult r = filter.run(c.cloud, o.choice.params);
  o.auto_seconds = seconds_since(t);
  o.auto_passes = r.summary.passes_run;
  o.auto_rms = rms_line_angle(r.normals, c.truth);
  return o;
}

std::string setting_text(const Setting& s) {
  char text[64];
  if (s.sigma_g >= 1e5) {
    std::snprintf(text, sizeof text, "%g/off/%d", s.sigma_f, s.passes);
  } else {
    std::snprintf(text, sizeof text, "%g/%g/%d", s.sigma_f, s.sigma_g, s.passes);
  }
  return text;
}

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
  std::vector<std::string> shapes = {"plane", "sphere", "cube", "wedges", "cylinder", "torus"};
  std::vector<double> noises = {0, 0.25, 0.5};
  std::vector<int> pca_ks = {16, 64};
  std::vector<int> fandisk_levels = {0, 1, 2, 3};
  std::vector<std::string> grid_files;
  app.add_flag("--quick", quick, "plane, cube and torus at noise 0 and 0.5, PCA-16 only; fandisk levels 0 and 2");
  app.add_flag("--no-grid", no_grid, "skip the grid search (auto and paper only)");
  app.add_flag("--no-synthetic", no_synthetic, "skip the synthetic shapes");
  app.add_flag("--no-fandisk", no_fandisk, "skip fandisk");
  app.add_option("--shapes", shapes, "synthetic shapes to run");
  app.add_option("--noise", noises, "synthetic position noise levels, in spacings (per axis)");
  app.add_option("--pca", pca_ks, "PCA neighbourhood sizes for the synthetic input normals");
  app.add_option("--fandisk-levels", fandisk_levels,
                 "fandisk noise levels to run: 0..3 = 0, 0.125, 0.6, 1.2% of diagonal");
  app.add_option("--points", points, "points per synthetic shape (default 20000)");
  app.add_option("--data", data_dir, "folder with fandisk100k.xyz and fandisk100k.normals");
  app.add_option("--json", json_path, "write every case, the grid included, as JSON");
  app.add_option("--grid-from", grid_files,
                 "JSON files of earlier runs: a case found there (same name, same seeds) reuses its grid instead "
                 "of running it again, so a change of the rule costs only the --auto runs");
  app.add_option("--backend", backend, "opencl (default) or reference")->check(CLI::IsMember({"opencl", "reference"}));
  app.add_option("--device", device, "OpenCL device selector");
  CLI11_PARSE(app, argc, argv);
  if (quick) {
    shapes = {"plane", "cube", "torus"};
    noises = {0, 0.5};
    pca_ks = {16};
    fandisk_levels = {0, 2};
  }

  FilterOptions options;
  options.device = backend == "reference" ? Device::reference() : Device::parse(device);
  NormalFilter filter(options);
  std::printf("pnf_eval_auto on %s\n", filter.device_description().c_str());
  std::printf(
      "RMS angle to the true normals as lines, degrees. Settings: sigma_f/sigma_g/passes; grid and paper in\n"
      "mean radii (pnf default units), auto in estimated spacings. ratio = auto / best of grid.\n\n");
  std::printf("%-24s %6s %6s %6s %7s %13s %7s %13s %6s  %s\n", "case", "input", "paper", "best", "auto", "best setting",
              "", "auto setting", "ratio",
              "estimate: spacing/radius, noise in spacings (true), normals deg, features %, curved %, normal error "
              "correlation");

  std::vector<std::pair<Case, Outcome>> results;
  auto report = [&](Case& c, const Outcome& o) {
    const DataEstimate& e = o.choice.estimate;
    std::printf("%-24s %6.2f %6.2f %6.2f %7.2f %13s %7s %13s %6s  %.3f, %.2f (%.2f), %.1f, %.0f, %.0f, %.2f\n",
                c.name.c_str(), o.input_rms, o.paper_rms, no_grid ? 0.0 : o.best.rms, o.auto_rms,
                no_grid ? "-" : setting_text(o.best).c_str(), "", auto_text(o).c_str(), ratio_text(o, no_grid).c_str(),
                e.area_spacing / o.mean_radius, e.position_noise_area_spacings(), c.true_noise / e.area_spacing, e.normal_noise_deg,
                100 * e.feature_share, 100 * e.curved_share, e.normal_error_correlation);
    std::fflush(stdout);
    c.cloud = {};
    c.truth = {};
    results.emplace_back(c, o);
  };

  if (!no_synthetic) {
    // Seeds follow the shape and the noise level, not the order asked for, so a case has the
    // same points in every selection (and --grid-from finds its grid).
    const std::vector<std::string> all_shapes = {"plane", "sphere", "cube", "wedges", "cylinder", "torus"};
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
        for (int k : pca_ks) {
          Case c;
          char label[64];
          std::snprintf(label, sizeof label, "%s n%.2g pca%d", name.c_str(), noise, k);
          c.name = label;
          c.family = "synthetic";
          std::snprintf(label, sizeof label, "%.2g", noise);
          c.noise_label = label;
          c.pca_neighbours = k;
          c.cloud.positions = noisy;
          c.cloud.normals = pca_normals(noisy, shape.normals, k);
          c.truth = shape.normals;
          c.true_spacing = spacing;
          c.true_noise = noise * spacing;
          report(c, evaluate(filter, c, !no_grid, grid_files));
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
        report(c, evaluate(filter, c, !no_grid, grid_files));
      }
    }
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
          << ", \"auto\": " << o.auto_rms << ", \"best\": " << (no_grid ? 0.0 : o.best.rms) << ", \"best_setting\": \""
          << (no_grid ? "" : setting_text(o.best)) << "\", \"auto_setting\": \"" << auto_text(o)
          << "\", \"mean_radius\": " << o.mean_radius << ", \"spacing\": " << e.area_spacing
          << ", \"noise_spacings\": " << e.position_noise_area_spacings() << ", \"true_noise\": " << c.true_noise
          << ", \"normal_noise_deg\": " << e.normal_noise_deg << ", \"feature_share\": " << e.feature_share
          << ", \"curved_share\": " << e.curved_share
          << ", \"normal_error_correlation\": " << e.normal_error_correlation << ", \"rule\": \""
          << json_escape(o.choice.rule) << "\", \"grid\": [";
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
