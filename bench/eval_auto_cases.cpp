// pnf_eval_auto's evaluation of one case (eval_auto_cases.hpp).
#include "eval_auto_cases.hpp"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <sstream>

#include "eval_clouds.hpp"
#include "pnf/mean_radius.hpp"

namespace pnf::eval {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

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

Outcome evaluate(NormalFilter& filter, const Case& c, bool grid, const std::vector<std::string>& grid_files,
                 const Grid& spec, bool estimate_only) {
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
  // The whole --auto run: the choice and its judged passes (improve_normals_auto).
  auto t = std::chrono::steady_clock::now();
  std::vector<Vec3> normals(c.cloud.size());
  const AutoRun run = improve_normals_auto(c.cloud, MutableVec3ArrayView(normals), filter);
  o.choice = run.choice;
  o.estimate_seconds = 0;
  o.auto_seconds = seconds_since(t);
  o.auto_passes = run.passes_kept;
  o.auto_rms = rms_line_angle(normals, c.truth);
  return o;
}

}  // namespace pnf::eval
