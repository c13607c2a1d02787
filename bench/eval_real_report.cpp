// pnf_eval_real's report (eval_real_report.hpp).
#include "eval_real_report.hpp"

#include <cstdio>
#include <fstream>

#include "eval_clouds.hpp"

namespace pnf::eval {
namespace {

std::string ratio_text(const Outcome& o) {
  if (!o.grid_run || o.best.error.rms_deg < kTinyError) return "-";
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", o.automatic.rms_deg / o.best.error.rms_deg);
  return text;
}

std::string grid_seconds_text(const Outcome& o) {
  if (!o.grid_run) return "-";
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", o.grid_seconds);
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

std::string setting_text(const Setting& s) {
  return s.passes == 0 ? "input" : eval::setting_text(s.sigma_f, s.sigma_g, s.passes);
}

std::string error_text(const AngleError& e) {
  char text[48];
  std::snprintf(text, sizeof text, "%.2f / %.2f", e.rms_deg, e.mean_deg);
  return text;
}

bool not_worse(const AngleError& a, const AngleError& input) {
  return a.rms_deg <= input.rms_deg + kSameAsInputDeg && a.mean_deg <= input.mean_deg + kSameAsInputDeg;
}

void print_report(const ReportHeading& h, const std::vector<Outcome>& outcomes, const std::vector<ModelInfo>& infos) {
  std::printf("pnf_eval_real on %s, commit %s, %zu points a model, seed %llu\n\n", h.description.c_str(),
              h.commit.c_str(), h.points, static_cast<unsigned long long>(h.seed));
  std::printf(
      "Oriented angle to the true normals, RMS / mean, degrees. Noise: sigma per axis, fraction of the bounding-box "
      "diagonal (1). Settings sigma_f/sigma_g/passes in mean radii. ratio = auto / best (RMS). auto<=in: no worse "
      "than the input in RMS and mean. Times in seconds: normals = the input normals' estimate; auto = choice + "
      "filter.\n\n");
  std::printf(
      "| model | family | noise | normals | input | paper | auto | best | best setting | ratio | auto<=in | normals s "
      "| paper s | auto s | grid s |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  int worse = 0, over = 0, graded = 0;
  for (const Outcome& o : outcomes) {
    const bool ok = not_worse(o.automatic, o.input);
    if (!ok && o.normals != "exact") ++worse;
    if (o.grid_run && o.best.error.rms_deg >= kTinyError) {
      ++graded;
      if (o.automatic.rms_deg > kWithinOfBest * o.best.error.rms_deg) ++over;
    }
    std::printf("| %s | %s | %g | %s | %s | %s | %s | %s | %s | %s | %s | %.2f | %.2f | %.2f | %s |\n", o.model.c_str(),
                o.family.c_str(), o.noise, o.normals.c_str(), error_text(o.input).c_str(), error_text(o.paper).c_str(),
                error_text(o.automatic).c_str(), o.grid_run ? error_text(o.best.error).c_str() : "-",
                o.grid_run ? setting_text(o.best).c_str() : "-", ratio_text(o).c_str(), ok ? "yes" : "no",
                o.normals_seconds, o.paper_seconds, o.auto_seconds, grid_seconds_text(o).c_str());
  }
  std::printf("\n%zu cases: %d worse than their input (exact input not counted)", outcomes.size(), worse);
  if (h.grid) std::printf("; %d of %d graded more than 10%% above the grid's best", over, graded);
  std::printf("\n\n| model | noise | normals | auto's choice |\n|---|---|---|---|\n");
  for (const Outcome& o : outcomes) {
    std::printf("| %s | %g | %s | %s |\n", o.model.c_str(), o.noise, o.normals.c_str(), o.rule.c_str());
  }
  std::printf(
      "\n| model | vertices | triangles | degenerate | welded vertices | boundary edges | non-manifold edges | "
      "misoriented edges | flipped | sharp corners | read s | truth + samples s |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const ModelInfo& m : infos) {
    if (m.triangles == 0) {  // a point set: its normals are the truth
      std::printf("| %s | %zu | - | - | - | - | - | - | - | - | %.2f | - |\n", m.name.c_str(), m.vertices,
                  m.read_seconds);
      continue;
    }
    std::printf("| %s | %zu | %zu | %zu | %zu | %zu | %zu | %zu | %s | %.1f%% | %.2f | %.2f |\n", m.name.c_str(),
                m.vertices, m.triangles, m.stats.degenerate, m.stats.welded, m.stats.boundary_edges,
                m.stats.nonmanifold_edges, m.stats.misoriented_edges, m.stats.flipped ? "yes" : "no",
                100.0 * double(m.stats.sharp_corners) / double(3 * m.triangles), m.read_seconds, m.sample_seconds);
  }
}

void write_json(const std::string& path, const ReportHeading& h, const std::vector<Outcome>& outcomes,
                const std::vector<ModelInfo>& infos) {
  std::ofstream out(path);
  auto error_json = [](const AngleError& e) {
    return "{\"rms\": " + std::to_string(e.rms_deg) + ", \"mean\": " + std::to_string(e.mean_deg) + "}";
  };
  out << "{\n  \"device\": \"" << json_escape(h.description) << "\", \"commit\": \"" << json_escape(h.commit)
      << "\", \"points\": " << h.points << ", \"seed\": " << h.seed << ",\n  \"models\": [\n";
  for (std::size_t i = 0; i < infos.size(); ++i) {
    const ModelInfo& m = infos[i];
    out << "    {\"name\": \"" << m.name << "\", \"family\": \"" << m.family << "\", \"vertices\": " << m.vertices
        << ", \"triangles\": " << m.triangles << ", \"degenerate\": " << m.stats.degenerate
        << ", \"welded\": " << m.stats.welded << ", \"boundary_edges\": " << m.stats.boundary_edges
        << ", \"nonmanifold_edges\": " << m.stats.nonmanifold_edges
        << ", \"misoriented_edges\": " << m.stats.misoriented_edges << ", \"signed_volume\": " << m.stats.signed_volume
        << ", \"flipped\": " << (m.stats.flipped ? "true" : "false") << ", \"sharp_corners\": " << m.stats.sharp_corners
        << ", \"read_seconds\": " << m.read_seconds << ", \"sample_seconds\": " << m.sample_seconds << "}"
        << (i + 1 < infos.size() ? "," : "") << "\n";
  }
  out << "  ],\n  \"cases\": [\n";
  for (std::size_t i = 0; i < outcomes.size(); ++i) {
    const Outcome& o = outcomes[i];
    out << "    {\"model\": \"" << o.model << "\", \"family\": \"" << o.family << "\", \"noise\": " << o.noise
        << ", \"normals\": \"" << o.normals << "\", \"input\": " << error_json(o.input)
        << ", \"paper\": " << error_json(o.paper) << ", \"auto\": " << error_json(o.automatic)
        << ", \"auto_not_worse\": " << (not_worse(o.automatic, o.input) ? "true" : "false") << ", \"rule\": \""
        << json_escape(o.rule) << "\", \"seconds\": {\"normals\": " << o.normals_seconds
        << ", \"paper\": " << o.paper_seconds << ", \"auto\": " << o.auto_seconds << ", \"grid\": " << o.grid_seconds
        << "}";
    if (o.grid_run) {
      out << ", \"best\": {\"setting\": \"" << setting_text(o.best) << "\", \"sigma_f\": " << o.best.sigma_f
          << ", \"sigma_g\": " << o.best.sigma_g << ", \"passes\": " << o.best.passes
          << ", \"rms\": " << o.best.error.rms_deg << ", \"mean\": " << o.best.error.mean_deg << "}, \"ratio\": "
          << (o.best.error.rms_deg >= kTinyError ? std::to_string(o.automatic.rms_deg / o.best.error.rms_deg)
                                                 : std::string("null"))
          << ", \"grid\": [";
      for (std::size_t g = 0; g < o.grid.size(); ++g) {
        const Setting& s = o.grid[g];
        out << (g ? ", " : "") << "[" << s.sigma_f << ", " << s.sigma_g << ", " << s.passes << ", " << s.error.rms_deg
            << ", " << s.error.mean_deg << "]";
      }
      out << "]";
    }
    out << "}" << (i + 1 < outcomes.size() ? "," : "") << "\n";
  }
  out << "  ]\n}\n";
}

}  // namespace pnf::eval
