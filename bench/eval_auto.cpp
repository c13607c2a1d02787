// pnf_eval_auto: how `--auto` (pnf/auto_params.hpp) compares with the paper's settings and with
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
// Prints a table and a summary against the targets (never worse than the input, within 10% of the
// grid's best), and with --json a file for bench/plot_auto.py and --grid-from.
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
// The held-out cases' jittered input normals: the true ones tilted by this RMS angle, degrees.
constexpr double kJitterRmsDeg = 8;

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

// A cylinder of radius r along z from 0 to `height`, closed by two flat caps, sampled uniformly
// over its area: a curved face meeting flat ones at 90-degree rims.
Shape capped_cylinder(const std::string& name, double r, double height, std::size_t points, std::mt19937& rng) {
  std::uniform_real_distribution<double> u01(0, 1);
  const double side = 2 * kPi * r * height, cap = kPi * r * r;
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
  if (name == "fold") {
    // A sheet folded twice along parallel lines, at gentle dihedral angles only (125 and 145
    // degrees): the tuning shape for creases that each pass blurs rather than sharpens (the
    // held-out family's single creases are at other angles).
    const double up = 55 * kPi / 180, back = 20 * kPi / 180;
    const Vec3 p1 = {0.6, 0, 0}, p2 = add(p1, {0.6 * std::cos(up), 0, 0.6 * std::sin(up)});
    const Vec3 p3 = add(p2, {0.6 * std::cos(back), 0, 0.6 * std::sin(back)});
    const std::vector<Vec3> profile = {{0, 0, 0}, p1, p2, p3};
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
    return capped_cylinder(name, 0.5, 1, points, rng);
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

// The held-out family of issue 14, made before the rule was changed and never used to fit it:
// shapes that are mostly smooth or flat with a few creases, at densities 4 and 20 times the tuned
// cases'. Each is sampled uniformly at random over its area.
//
// A single crease: two unit squares meeting along the y axis at the dihedral angle `degrees`
// (180 would be one plane), so the crease is 1 long in an area of 2.
Shape make_crease(double degrees, std::size_t points, unsigned seed) {
  std::mt19937 rng(seed);
  const double t = degrees * kPi / 180;
  char name[32];
  std::snprintf(name, sizeof name, "crease%g", degrees);
  // Face b leaves the crease at the angle t to face a's direction (-1, 0, 0); both normals point
  // into the wedge between them, so one consistent side for the filter.
  return sample_patches(
      name, {{{-1, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 0, 0}, {-std::cos(t), 0, std::sin(t)}, {0, 1, 0}}}, points, rng);
}

// A long capped cylinder (radius 0.25, height 2: other proportions than the tuned "cylinder"):
// a curved face with two 90-degree rims, 3.1 of crease length in an area of 3.5.
Shape make_long_cylinder(std::size_t points, unsigned seed) {
  std::mt19937 rng(seed);
  return capped_cylinder("longcyl", 0.25, 2, points, rng);
}

// A rounded box: 1 x 1 x 0.6, its four vertical edges rounded with radius 0.2 (smooth: tangent
// continuous), its top and bottom rims sharp (90 degrees, 7.3 of crease length in an area of 4.2).
Shape make_rounded_box(std::size_t points, unsigned seed) {
  constexpr double half = 0.5, r = 0.2, height = 0.6, inner = half - r;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u01(0, 1);
  const double flat_side = 4 * (2 * inner) * height, round_side = 2 * kPi * r * height;
  const double cap = 4 * half * half - (4 - kPi) * r * r;
  Shape shape;
  shape.name = "roundbox";
  shape.area = flat_side + round_side + 2 * cap;
  std::discrete_distribution<int> part({flat_side, round_side, 2 * cap});
  for (std::size_t i = 0; i < points; ++i) {
    const int which = part(rng);
    const double z = height * u01(rng);
    if (which == 0) {  // one of the four flat sides, rotated by multiples of 90 degrees
      const int k = int(4 * u01(rng)) % 4;
      const double along = (2 * u01(rng) - 1) * inner;
      const double c = std::cos(k * kPi / 2), s = std::sin(k * kPi / 2);
      shape.positions.push_back({c * half - s * along, s * half + c * along, z});
      shape.normals.push_back({c, s, 0});
    } else if (which == 1) {  // a rounded edge: angle a about its corner's axis
      const double a = 2 * kPi * u01(rng);
      const double cx = std::cos(a) >= 0 ? inner : -inner, cy = std::sin(a) >= 0 ? inner : -inner;
      shape.positions.push_back({cx + r * std::cos(a), cy + r * std::sin(a), z});
      shape.normals.push_back({std::cos(a), std::sin(a), 0});
    } else {  // top or bottom: a rounded square, by rejection
      double x = 0, y = 0;
      for (;;) {
        x = (2 * u01(rng) - 1) * half, y = (2 * u01(rng) - 1) * half;
        const double dx = std::max(0.0, std::fabs(x) - inner), dy = std::max(0.0, std::fabs(y) - inner);
        if (dx * dx + dy * dy <= r * r) break;
      }
      const bool top = u01(rng) < 0.5;
      shape.positions.push_back({x, y, top ? height : 0});
      shape.normals.push_back({0, 0, top ? 1.0 : -1.0});
    }
  }
  return shape;
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

// The true normals, each tilted by a Gaussian angle of `rms_degrees` RMS (Rayleigh
// distributed magnitude, uniform direction): errors independent from point to point, unlike PCA's.
std::vector<Vec3> jittered_normals(const std::vector<Vec3>& truth, double rms_degrees, unsigned seed) {
  std::mt19937 rng(seed);
  // Per tangent axis sigma = RMS / sqrt(2); tan, since the tilt is added as a tangent vector.
  std::normal_distribution<double> g(0, std::tan(rms_degrees / std::sqrt(2.0) * kPi / 180));
  std::vector<Vec3> normals;
  normals.reserve(truth.size());
  for (const Vec3& n : truth) {
    const Vec3 helper = std::fabs(n[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    const Vec3 t1 = unit(cross(n, helper)), t2 = cross(n, t1);
    normals.push_back(unit(add(n, add(scale(t1, g(rng)), scale(t2, g(rng))))));
  }
  return normals;
}

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

// The settings a grid search tries: every sigma_f with every sigma_g, one pass at a time up to the
// largest of `passes`, scored after each pass listed there.
struct Grid {
  std::vector<double> sigma_f, sigma_g;
  std::vector<int> passes;
};
const Grid kFullGrid{{std::begin(kGridSigmaF), std::end(kGridSigmaF)},
                     {std::begin(kGridSigmaG), std::end(kGridSigmaG)},
                     {std::begin(kGridPasses), std::end(kGridPasses)}};
// For the held-out cases above --full-grid-points (400k points: one full grid there costs about
// 20 times a 20k one): the sigma_g that the tuned cases' optima used (0.25-2 and off), sigma_f at
// the ends of the full grid, and the passes at 2 and 8 (the full grid's optima on shapes with
// edges were at 4-8 passes, on smooth curved ones at 1-2).
const Grid kCoarseGrid{{2, 8}, {0.25, 1, 1e6}, {2, 8}};
// Gaussian averaging: the paper's sigma_f and passes with the feature term off (sigma_g "off").
constexpr double kGaussianSigmaG = 1e6;

Outcome evaluate(NormalFilter& filter, const Case& c, bool grid, const std::vector<std::string>& grid_files,
                 const Grid& spec = kFullGrid, bool estimate_only = false) {
  Outcome o;
  o.input_rms = rms_line_angle(c.cloud.normals, c.truth);
  o.mean_radius = estimate_mean_radius(c.cloud.positions);
  if (estimate_only) {  // the rule's choice and its measurements, no filtering
    o.choice = choose_filter_params(c.cloud);
    return o;
  }
  o.paper_rms = o.gaussian_rms = -1;
  // A cached grid serves without --no-grid too: then it holds at least the paper's and the
  // Gaussian setting of an earlier run, which are not run again.
  for (const std::string& file : grid_files) {
    if (!o.grid.empty()) break;
    o.grid = cached_grid(file, c.name);
  }
  auto note = [&](const Setting& s) {
    if (s.rms < o.best.rms) o.best = s;
    if (s.sigma_f == kPaper.sigma_f && s.passes == kPaper.iterations) {
      if (s.sigma_g == kPaper.sigma_g) o.paper_rms = s.rms;
      if (s.sigma_g == kGaussianSigmaG) o.gaussian_rms = s.rms;
    }
  };
  o.best.rms = 1e9;
  if (!o.grid.empty()) {
    for (const Setting& s : o.grid) note(s);
  } else if (grid) {
    const int max_passes = *std::max_element(spec.passes.begin(), spec.passes.end());
    for (double sf : spec.sigma_f) {
      for (double sg : spec.sigma_g) {
        PointCloud step = c.cloud;
        FilterParams params;
        params.sigma_f = sf;
        params.sigma_g = sg;
        params.iterations = 1;
        params.mean_radius = o.mean_radius;
        for (int pass = 1; pass <= max_passes; ++pass) {
          step.normals = filter.run(step, params).normals;
          if (std::find(spec.passes.begin(), spec.passes.end(), pass) == spec.passes.end()) continue;
          const Setting s{sf, sg, pass, rms_line_angle(step.normals, c.truth)};
          o.grid.push_back(s);
          note(s);
        }
      }
    }
  }
  // Outside the grid (or without one): run the two fixed settings themselves. They join the grid
  // (and the JSON file, so that --grid-from finds them).
  for (const double sigma_g : {kPaper.sigma_g, kGaussianSigmaG}) {
    double& rms = sigma_g == kPaper.sigma_g ? o.paper_rms : o.gaussian_rms;
    if (rms >= 0) continue;
    FilterParams params = kPaper;
    params.sigma_g = sigma_g;
    params.mean_radius = o.mean_radius;
    rms = rms_line_angle(filter.run(c.cloud, params).normals, c.truth);
    o.grid.push_back({params.sigma_f, sigma_g, params.iterations, rms});
    note(o.grid.back());
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
  app.add_option("--pca", pca_ks, "PCA neighbourhood sizes for the synthetic input normals");
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
              "correlation, crease length per size, normal-position coupling, crease sharpness");

  std::vector<std::pair<Case, Outcome>> results;
  auto report = [&](Case& c, const Outcome& o) {
    const DataEstimate& e = o.choice.estimate;
    std::printf("%-24s %6.2f %6.2f %6.2f %6.2f %7.2f %13s %13s %6s  %.3f, %.2f (%.2f), %.1f, %.0f, %.0f, %.2f, %.2f, %.2f, %.3f\n",
                c.name.c_str(), o.input_rms, o.paper_rms, o.gaussian_rms, no_grid ? 0.0 : o.best.rms, o.auto_rms,
                no_grid ? "-" : setting_text(o.best).c_str(), auto_text(o).c_str(), ratio_text(o, no_grid).c_str(),
                e.area_spacing / o.mean_radius, e.position_noise_area_spacings(), c.true_noise / e.area_spacing,
                e.normal_noise_deg, 100 * e.feature_share, 100 * e.curved_share, e.normal_error_correlation,
                e.crease_length, e.normal_position_coupling, e.crease_sharpness);
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
        for (int k : pca_ks) run_case("pca" + std::to_string(k), pca_normals(noisy, shape.normals, k), k);
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
          << ", \"crease_sharpness\": " << e.crease_sharpness << ", \"rule\": \""
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
