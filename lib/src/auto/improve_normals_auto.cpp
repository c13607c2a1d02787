// pnf::improve_normals_auto: `pnf filter --auto` as one call (pnf/improve_normals_auto.hpp), and what it
// shares with the distributed one (judged_passes.hpp).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "cloud_checks.hpp"
#include "filter_engine.hpp"
#include "filter_plan.hpp"
#include "geometry.hpp"
#include "held_out_planes.hpp"
#include "judged_passes.hpp"
#include "pnf/error.hpp"
#include "pnf/improve_normals_auto.hpp"
#include "stein_risk.hpp"
#include "surface_judge.hpp"

namespace pnf {
namespace {

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

// The input normals' own noise (stein_noise_deg) and which reading it is.
std::string own_noise_text(const AutoChoice& choice) {
  const double noise = detail::stein_noise_deg(choice);
  const bool chords = noise < choice.estimate.normal_noise_neighbours_deg;
  return number(noise) + " deg, from " + (chords ? "the chords to their nearest points" : "their neighbours' normals");
}

// The same filter setting, whatever its passes.
bool is_setting(const FilterParams& a, const FilterParams& b) {
  return a.sigma_f == b.sigma_f && a.sigma_g == b.sigma_g && a.units == b.units;
}

// improve_normals_auto where Stein's estimate decides (detail::stein_decides): for each setting,
// its passes from the probed input (kept at the estimate's samples) and from the input over the
// same neighbour lists, in turn pass by pass (the twin run), each pass estimated as it ends; the
// passes end two past the setting's lowest estimate, and the lowest of all settings is kept if the surface judge does
// not score it above the input (a veto against a noise estimate gone wrong); the judge scores only the pass kept.
// `input`: the input normals, unit.
AutoRun stein_run(const CloudView& cloud, MutableVec3ArrayView normals_out, NormalFilter& filter,
                  const ProgressCallback& progress, const detail::SurfaceJudge& judge, const std::vector<double>& input,
                  AutoRun& run) {
  const std::vector<FilterParams> candidates = detail::stein_candidates(run.choice);
  const detail::SteinRisk risk(detail::stein_samples(cloud.positions), input, detail::stein_noise_deg(run.choice));
  const std::vector<double> probed_input = risk.probed(input);
  std::vector<double> best = input;
  std::vector<Vec3> scratch(cloud.size());  // each run's output (the observers copy what they keep)
  double best_risk = risk.input_risk_deg();
  std::size_t best_candidate = 0;
  std::string estimated = detail::stein_heading(run.choice);
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    FilterParams params = candidates[c];
    params.iterations = detail::judged_pass_budget(params, run.choice, judge.scored());
    std::vector<std::vector<double>> probed_by_pass;
    auto after_probed_pass = [&](int, const std::vector<double>& normals) {
      probed_by_pass.push_back(risk.at_samples(normals.data()));
      return true;
    };
    std::vector<double> risk_by_pass = {risk.input_risk_deg()};
    int best_pass_here = 0;
    auto after_pass = [&](int pass, const std::vector<double>& normals) {
      // The probed run's stop rule may have ended it before this pass, which then has no estimate.
      if (std::size_t(pass) > probed_by_pass.size()) return false;
      risk_by_pass.push_back(risk.risk_deg(risk.at_samples(normals.data()), probed_by_pass[std::size_t(pass) - 1]));
      if (risk_by_pass.back() < risk_by_pass[std::size_t(best_pass_here)]) best_pass_here = pass;
      if (risk_by_pass.back() < best_risk) {
        best_risk = risk_by_pass.back();
        best = normals;
        best_candidate = c;
        run.passes_kept = pass;
      }
      return !detail::judged_passes_end(risk_by_pass, best_pass_here, detail::kNoBar, params.iterations);
    };
    const FilterSummary summary =
        filter.run_observed_after_twin(cloud, Vec3ArrayView(probed_input.data(), cloud.size()), after_probed_pass,
                                       MutableVec3ArrayView(scratch), params, after_pass, progress);
    if (c == best_candidate) run.summary = summary;
    estimated += detail::judged_candidate(c, params, risk_by_pass);
    run.judged_rms_deg.insert(run.judged_rms_deg.end(), risk_by_pass.begin() + 1, risk_by_pass.end());
  }
  const double input_judged = judge.input_rms_deg(input.data());
  const double best_judged = run.passes_kept > 0 ? judge.rms_deg(best.data()) : 0.0;
  if (best_judged > input_judged) {
    run.passes_kept = 0;
    best = input;
  }
  for (std::size_t i = 0; i < cloud.size(); ++i) normals_out.set(i, {best[3 * i], best[3 * i + 1], best[3 * i + 2]});
  if (run.passes_kept > 0) run.choice.params = candidates[best_candidate];
  run.choice.judged = detail::stein_judged(input_judged, best_judged) + estimated +
                      detail::judged_outcome(best_candidate, run.passes_kept);
  run.choice.params.iterations = run.passes_kept;
  return run;
}

}  // namespace

std::vector<FilterParams> detail::judged_candidates(const AutoChoice& choice) {
  std::vector<FilterParams> candidates = {choice.params};
  if (independent_normal_errors(choice)) {
    const FilterParams other = independent_errors_setting(choice);
    if (other.sigma_f != choice.params.sigma_f || other.sigma_g != choice.params.sigma_g) candidates.push_back(other);
  }
  const FilterParams smooth = smooth_detail_setting(choice);
  if (tries_smooth_detail(choice) && std::none_of(candidates.begin(), candidates.end(),
                                                  [&](const FilterParams& p) { return is_setting(p, smooth); })) {
    candidates.push_back(smooth);
  }
  return candidates;
}

bool detail::tries_smooth_detail(const AutoChoice& choice) { return judge_chooses_scale(choice); }

double detail::rms_to_beat(double input_rms_deg, double error_deg) {
  return std::sqrt(std::max(input_rms_deg * input_rms_deg - error_deg * error_deg, 0.0)) - error_deg;
}

bool detail::judged_passes_end(const std::vector<double>& rms_by_pass, int best_pass_here, double to_beat, int budget) {
  const int pass = int(rms_by_pass.size()) - 1;
  if (pass - best_pass_here >= kJudgedPassesPastBest) return true;
  if (pass < 2) return false;
  const double gain = rms_by_pass[std::size_t(pass) - 1] - rms_by_pass[std::size_t(pass)];
  const double gain_before = rms_by_pass[std::size_t(pass) - 2] - rms_by_pass[std::size_t(pass) - 1];
  return gain > 0 && gain < gain_before && std::isfinite(to_beat) &&
         rms_by_pass[std::size_t(pass)] - std::max(gain, gain_before) * (budget - pass) >= to_beat;
}

std::vector<FilterParams> detail::stein_candidates(const AutoChoice& choice) {
  std::vector<FilterParams> candidates = judged_candidates(choice);
  const FilterParams plain = plain_averaging_setting(choice);
  if (std::none_of(candidates.begin(), candidates.end(), [&](const FilterParams& p) { return is_setting(p, plain); })) {
    candidates.push_back(plain);
  }
  return candidates;
}

int detail::judged_pass_budget(const FilterParams& params, const AutoChoice& choice, int fit_points) {
  if (on_independent_errors_line(choice, params) || is_setting(params, plain_averaging_setting(choice))) {
    return params.iterations;
  }
  const int budget = std::max(params.iterations, kJudgedPassBudget);
  return noise_hides_features(choice.estimate) ? passes_within_fits(choice, params, fit_points, budget) : budget;
}

std::string detail::judged_heading(double input_rms_deg, double own_error_deg, double error_deg, std::size_t samples,
                                   int fit_points, int under_support) {
  const std::string support =
      under_support > 0 ? ", under the " + std::to_string(under_support) + " whose plane the input follows" : "";
  const std::string floor =
      error_deg > own_error_deg ? ", at least " + number(error_deg) + " by the input normals' own noise" : "";
  return "judged against the surface fitted to the positions at " + std::to_string(samples) + " points (fits of " +
         std::to_string(fit_points) + " points" + support + ", its own error " + number(own_error_deg) + " deg" +
         floor + "), RMS deg from the input (" + number(input_rms_deg) +
         ", to beat: " + number(rms_to_beat(input_rms_deg, error_deg)) + ") by pass:";
}

std::string detail::judged_candidate(std::size_t candidate, const FilterParams& params,
                                     const std::vector<double>& rms_by_pass) {
  std::string text = candidate == 0 ? " rule's setting"
                                    : "; sigma_f " + number(params.sigma_f) + ", sigma_g " +
                                          (feature_term_off(params) ? std::string("off") : number(params.sigma_g));
  for (std::size_t pass = 1; pass < rms_by_pass.size(); ++pass) text += " " + number(rms_by_pass[pass]);
  return text;
}

std::string detail::judged_budget_note(const FilterParams& setting, int budget) {
  if (budget >= setting.iterations) return "";
  return " (its " + std::to_string(setting.iterations) + " passes held to " + std::to_string(budget) +
         ", as many as the judge's fits reach)";
}

std::string detail::judged_outcome(std::size_t best_candidate, int passes_kept) {
  if (passes_kept == 0) return ": the input normals kept";
  const char* names[] = {"the rule's setting", "the other setting", "the third setting",
                         "the fallback",       "the narrow pass",   "the held-out check's pass"};
  return std::string(": ") + names[std::min(best_candidate, kHeldOutCandidate)] + ", " + std::to_string(passes_kept) +
         (passes_kept == 1 ? " pass kept" : " passes kept");
}

bool detail::tries_fallback(const AutoChoice& choice) { return !judge_geometry(choice.estimate).quarter_allowed; }

double detail::fallback_to_beat(double input_rms_deg, double error_deg) {
  return std::sqrt(std::max(input_rms_deg * input_rms_deg - error_deg * error_deg, 0.0));
}

bool detail::tries_narrow_pass(const AutoChoice& choice, int plane_fits) {
  return judge_chooses_scale(choice) && plane_fits > 0;
}

double detail::narrow_pass_to_beat(double input_rms_deg, double error_deg) { return input_rms_deg + error_deg; }

double detail::pass_reach_points(const AutoChoice& choice, const FilterParams& params) {
  const DataEstimate& e = choice.estimate;
  if (!(e.area_spacing > 0) || !(e.mean_radius > 0)) return 0;
  const double reach = make_filter_plan(params, MeanRadius{e.mean_radius, e.radius_source}).reach;
  return geometry::kPi * reach * reach / (e.area_spacing * e.area_spacing);
}

int detail::passes_within_fits(const AutoChoice& choice, const FilterParams& params, int fit_points, int most) {
  const double reach = pass_reach_points(choice, params);
  if (!(reach > 0)) return 1;
  const double passes = std::floor(double(fit_points) / reach);
  return int(std::clamp(passes, 1.0, double(std::max(most, 1))));
}

int detail::fallback_pass_budget(const AutoChoice& choice, int plane_fits, int fit_points) {
  if (plane_fits <= 0) return 1;
  return passes_within_fits(choice, fallback_setting(choice), fit_points, kFallbackPlaneFitPasses);
}

detail::Fallback detail::fallback_of(const AutoChoice& choice, int plane_fits, int fit_points, double input_rms_deg,
                                     double error_deg) {
  Fallback fallback;
  if (tries_fallback(choice)) {
    fallback.params = fallback_setting(choice);
    fallback.params.iterations = fallback_pass_budget(choice, plane_fits, fit_points);
    fallback.to_beat = fallback_to_beat(input_rms_deg, error_deg);
    fallback.candidate = kFallbackCandidate;
  } else if (tries_narrow_pass(choice, plane_fits)) {
    fallback.params = smooth_detail_setting(choice);
    fallback.to_beat = narrow_pass_to_beat(input_rms_deg, error_deg);
    fallback.candidate = kNarrowPassCandidate;
    fallback.plane_fits = plane_fits;
  }
  return fallback;
}

std::string detail::judged_fallback(const Fallback& fallback, const std::vector<double>& rms_by_pass) {
  const FilterParams& params = fallback.params;
  std::string text = fallback.candidate == kNarrowPassCandidate
                         ? "; the input normals are plane fits of " + std::to_string(fallback.plane_fits) +
                               " points: narrow pass sigma_f " + number(params.sigma_f) + ", sigma_g " +
                               number(params.sigma_g)
                         : "; fallback sigma_f " + number(params.sigma_f) + ", sigma_g " + number(params.sigma_g);
  text += " (to beat: " + number(fallback.to_beat) + ")";
  for (std::size_t pass = 1; pass < rms_by_pass.size(); ++pass) text += " " + number(rms_by_pass[pass]);
  return text;
}

bool detail::judge_vetoes(double judged_deg, double input_deg) { return judged_deg > input_deg; }

bool detail::tries_held_out(const AutoChoice& choice, int plane_fits) {
  return tries_fallback(choice) && !stein_decides(choice) && plane_fits > 0;
}

std::vector<FilterParams> detail::held_out_settings(const AutoChoice& choice, int fit_points) {
  std::vector<FilterParams> settings = {choice.params, fallback_setting(choice)};
  settings[0].iterations = judged_pass_budget(settings[0], choice, fit_points);
  settings[1].iterations = kJudgedPassBudget;
  return settings;
}

std::string detail::held_out_heading(std::size_t samples, double input_deg) {
  return "; held-out check against the planes of the other half's points at " + std::to_string(samples) +
         " samples, disagreement deg from the input (" + number(input_deg) + ") by pass:";
}

void detail::prepare_judge(SurfaceJudge& judge, const AutoChoice& choice, const double* input) {
  if (judge_chooses_scale(choice)) {
    judge.choose_scale(input);
  } else if (tries_fallback(choice) && !stein_decides(choice)) {
    judge.measure_plane_fits(input);
  }
}

double detail::noise_bounding_judge_deg(const AutoChoice& choice, int plane_fits) {
  const double noise = stein_noise_deg(choice);
  return tries_fallback(choice) && !stein_decides(choice) && plane_fits == 0 && noise >= 0 ? noise : -1;
}

double detail::judge_error_deg(double input_rms_deg, double own_error_deg, double input_noise_deg) {
  if (input_noise_deg < 0) return own_error_deg;
  const double floor = std::sqrt(std::max(input_rms_deg * input_rms_deg - input_noise_deg * input_noise_deg, 0.0));
  return std::max(own_error_deg, floor);
}

bool detail::judge_cannot_see_gains(const AutoChoice& choice, int plane_fits, double error_deg) {
  const double noise = noise_bounding_judge_deg(choice, plane_fits);
  return noise >= 0 && noise < error_deg;
}

std::string detail::unseen_gains_judged(const AutoChoice& choice, double input_rms_deg, double own_error_deg,
                                        double error_deg) {
  const std::string error = error_deg > own_error_deg ? "at least " + number(error_deg) + " deg (its own error " +
                                                            number(own_error_deg) + " deg)"
                                                      : number(error_deg) + " deg";
  return "judged against the surface fitted to the positions: the input " + number(input_rms_deg) +
         " deg, the judge's error " + error + ", above the input normals' own noise (" + own_noise_text(choice) +
         "), and they are no plane fits: no pass could be judged" + judged_outcome(0, 0);
}

bool detail::judge_fits_too_wide(int fit_points, std::size_t cloud_points) {
  return 2 * std::size_t(std::max(fit_points, 0)) > cloud_points;
}

std::string detail::too_wide_heading(std::size_t samples, int fit_points, std::size_t cloud_points) {
  return "judged against the surface fitted to the positions at " + std::to_string(samples) + " points (fits of " +
         std::to_string(fit_points) + " points, more than half of the " + std::to_string(cloud_points) +
         "): fits that wide follow the cloud's overall shape and vouch for no pass";
}

bool detail::stein_decides(const AutoChoice& choice) {
  return independent_normal_errors(choice) && choice.estimate.normal_noise_neighbours_deg > 0;
}

double detail::stein_noise_deg(const AutoChoice& choice) {
  const DataEstimate& e = choice.estimate;
  return e.normal_noise_chords_deg >= 0 ? std::min(e.normal_noise_neighbours_deg, e.normal_noise_chords_deg)
                                        : e.normal_noise_neighbours_deg;
}

bool detail::judge_chooses_scale(const AutoChoice& choice) {
  return judge_geometry(choice.estimate).quarter_allowed && !stein_decides(choice);
}

std::string detail::stein_judged(double input_rms_deg, double kept_rms_deg) {
  return "judged against the surface fitted to the positions: the input " + number(input_rms_deg) + " deg" +
         (kept_rms_deg > 0 ? ", the pass of lowest estimate " + number(kept_rms_deg) + " deg" : std::string());
}

std::string detail::stein_heading(const AutoChoice& choice) {
  return "; Stein's risk estimate (the input normals' noise " + own_noise_text(choice) + "), RMS deg by pass:";
}

AutoRun improve_normals_auto(const CloudView& cloud, MutableVec3ArrayView normals_out, NormalFilter& filter,
                             const ProgressCallback& progress, double stop_change_deg) {
  if (normals_out.count != cloud.size()) {
    throw Error(ErrorCode::invalid_argument, "improve_normals_auto: the output normals hold " +
                                                 std::to_string(normals_out.count) + " rows for " +
                                                 std::to_string(cloud.size()) + " points");
  }
  // The filter's own checks, before the estimate and the judge read the normals.
  detail::CloudRequirements requirements = detail::CloudRequirements::filter();
  requirements.caller = "improve_normals_auto";
  detail::check_cloud(cloud, requirements);
  // The estimate and the judge's neighbourhoods (under a second per 100k points) report as one
  // stage, their neighbour searches about every 0.1 s (a cancel honoured there); the passes then
  // report as the filter's do.
  const auto start = std::chrono::steady_clock::now();
  auto estimate_stage = [&](double fraction) {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (progress && !progress(PassProgress{0, 0, seconds, ProgressStage::estimate, fraction})) {
      throw Error(ErrorCode::cancelled, "improve_normals_auto: cancelled while estimating the data");
    }
  };
  estimate_stage(0);
  detail::SurfaceJudge judge;
  AutoRun run;
  run.choice = choose_filter_params(detail::estimate_data(cloud, &judge, [&](double fraction) {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return !progress || progress(PassProgress{0, 0, seconds, ProgressStage::estimate, 0.9 * fraction});
  }));
  estimate_stage(1);
  if (stop_change_deg >= 0) run.choice.params.stop_change_deg = stop_change_deg;
  if (run.choice.params.iterations == 0 || judge.empty()) {
    run.summary = filter.run(cloud, normals_out, run.choice.params, progress);
    run.passes_kept = run.summary.passes_run;
    return run;
  }
  const std::vector<FilterParams> candidates = detail::judged_candidates(run.choice);
  // Copies: normals_out may be the cloud's own normals, and every run must read the input, so
  // the runs write elsewhere and normals_out gets the normals kept at the end.
  const std::vector<double> input = detail::unit_rows(cloud.normals);
  detail::prepare_judge(judge, run.choice, input.data());
  if (detail::stein_decides(run.choice)) return stein_run(cloud, normals_out, filter, progress, judge, input, run);
  std::vector<double> best = input;
  std::vector<Vec3> scratch(cloud.size());
  const detail::SurfaceJudge::Sums input_sums = judge.input_sums(input.data());
  const double input_rms = input_sums.rms_deg();
  const double own_error = input_sums.own_error_deg();
  const double error =
      detail::judge_error_deg(input_rms, own_error, detail::noise_bounding_judge_deg(run.choice, judge.plane_fits()));
  if (detail::judge_cannot_see_gains(run.choice, judge.plane_fits(), error)) {
    // No pass: the input normals made unit, with the summary (radius, sigmas, lists) a run of the
    // rule's setting reports, as where the rule chooses no pass.
    run.choice.params.iterations = 0;
    run.summary = filter.run(cloud, normals_out, run.choice.params, progress);
    run.choice.judged = detail::unseen_gains_judged(run.choice, input_rms, own_error, error);
    return run;
  }
  std::size_t best_candidate = 0;
  // The held-out check (judged_passes.hpp), where it may run: its planes and the best pass it
  // has seen, kept apart from the judge's until the judge's settings and fallback keep the input.
  const bool held_out = detail::tries_held_out(run.choice, judge.plane_fits());
  const bool too_wide = detail::judge_fits_too_wide(judge.scored(), cloud.size());
  if (too_wide && !held_out) {  // no pass to judge by (judged_passes.hpp): the input, as above
    run.choice.params.iterations = 0;
    run.summary = filter.run(cloud, normals_out, run.choice.params, progress);
    run.choice.judged =
        detail::too_wide_heading(judge.size(), judge.scored(), cloud.size()) + detail::judged_outcome(0, 0);
    return run;
  }
  const detail::HeldOutPlanes planes =
      held_out ? detail::HeldOutPlanes(cloud.positions, input) : detail::HeldOutPlanes();
  const double held_out_input = planes.score(input.data()).disagreement_deg;
  double held_out_best = held_out_input;
  std::vector<double> held_out_normals;
  FilterParams held_out_params;
  int held_out_passes = 0;
  FilterSummary held_out_summary;
  std::string held_out_text = detail::held_out_heading(planes.size(), held_out_input);
  // Runs `params` (the `candidate`) pass by pass: the judge scores its first `judged_passes`
  // passes, a pass under `to_beat` is kept and becomes the bar, and judged_passes_end says when
  // they end; where `setting` is one of held_out_settings' (its number, else -1), the held-out
  // check scores every pass too, until the judge keeps one or the check's own passes end.
  // Returns the judge's RMS by pass.
  auto judged_run = [&](const FilterParams& params, std::size_t candidate, double& to_beat, int judged_passes,
                        int setting) {
    std::vector<double> rms_by_pass = {input_rms}, checked_by_pass = {held_out_input};
    int best_pass_here = 0, checked_best_here = 0;
    bool judging = judged_passes > 0, checking = setting >= 0, checked_best = false;
    auto after_pass = [&](int pass, const std::vector<double>& normals) {
      double judged_here = -1;  // the judge's score of this pass, where it scored it
      if (judging) {
        judged_here = judge.rms_deg(normals.data());
        rms_by_pass.push_back(judged_here);
        if (rms_by_pass.back() < rms_by_pass[std::size_t(best_pass_here)]) best_pass_here = pass;
        if (rms_by_pass.back() < to_beat) {
          to_beat = rms_by_pass.back();
          best = normals;
          best_candidate = candidate;
          run.passes_kept = pass;
        }
        judging =
            pass < judged_passes && !detail::judged_passes_end(rms_by_pass, best_pass_here, to_beat, judged_passes);
      }
      checking = checking && run.passes_kept == 0;
      if (checking) {
        const detail::HeldOutPlanes::Score score = planes.score(normals.data());
        checked_by_pass.push_back(score.disagreement_deg);
        if (score.disagreement_deg < checked_by_pass[std::size_t(checked_best_here)]) checked_best_here = pass;
        if (score.disagreement_deg < held_out_best && score.gain_z >= detail::kHeldOutMinGainZ &&
            !detail::judge_vetoes(judged_here >= 0 ? judged_here : judge.rms_deg(normals.data()), input_rms)) {
          held_out_best = score.disagreement_deg;
          held_out_normals = normals;
          held_out_params = params;
          held_out_passes = pass;
          checked_best = true;
        }
        checking = !detail::judged_passes_end(checked_by_pass, checked_best_here, detail::kNoBar, params.iterations);
      }
      return judging || checking;
    };
    const FilterSummary summary =
        filter.run_observed(cloud, MutableVec3ArrayView(scratch), params, after_pass, progress);
    if (candidate == best_candidate) run.summary = summary;
    if (checked_best) held_out_summary = summary;
    if (setting >= 0) held_out_text += detail::judged_candidate(std::size_t(setting), params, checked_by_pass);
    run.judged_rms_deg.insert(run.judged_rms_deg.end(), rms_by_pass.begin() + 1, rms_by_pass.end());
    return rms_by_pass;
  };
  // A pass must beat the input by more than the judge's error explains (judged_passes.hpp).
  double best_rms = detail::rms_to_beat(input_rms, error);
  // Where the judge's fits are too wide, only the held-out check runs and decides: the rule's
  // setting and the fallback's, each to the check's budget, none of their passes judged.
  std::string judged = too_wide ? detail::too_wide_heading(judge.size(), judge.scored(), cloud.size())
                                : detail::judged_heading(input_rms, own_error, error, judge.size(), judge.scored(),
                                                         judge.under_support());
  const std::vector<FilterParams> checked = detail::held_out_settings(run.choice, judge.scored());
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    FilterParams params = candidates[c];
    // The rule's passes are where it expects the gains to end; the judge decides, within a budget.
    params.iterations = detail::judged_pass_budget(params, run.choice, judge.scored());
    const int setting = held_out && c == 0 ? 0 : -1;  // held_out_settings' first is this one
    if (too_wide && setting < 0) continue;
    const std::vector<double> rms_by_pass = judged_run(params, c, best_rms, too_wide ? 0 : params.iterations, setting);
    if (!too_wide) {
      judged += detail::judged_candidate(c, params, rms_by_pass) +
                detail::judged_budget_note(candidates[c], params.iterations);
    }
  }
  const detail::Fallback fallback =
      detail::fallback_of(run.choice, judge.plane_fits(), judge.scored(), input_rms, error);
  if (run.passes_kept == 0 && fallback.candidate > 0) {
    double to_beat = fallback.to_beat;
    // With the held-out check, the fallback's setting (held_out_settings' second) runs on to the
    // check's budget; the judge scores its first passes (fallback_pass_budget).
    FilterParams params = fallback.params;
    if (held_out) params.iterations = checked[1].iterations;
    const std::vector<double> rms_by_pass =
        judged_run(params, fallback.candidate, to_beat, too_wide ? 0 : fallback.params.iterations, held_out ? 1 : -1);
    if (!too_wide) judged += detail::judged_fallback(fallback, rms_by_pass);
  }
  // The check's text only where it decided: where the judge kept a pass, the check stopped.
  if (run.passes_kept == 0 && held_out) judged += held_out_text;
  if (run.passes_kept == 0 && held_out_passes > 0) {
    best.swap(held_out_normals);
    best_candidate = detail::kHeldOutCandidate;
    run.passes_kept = held_out_passes;
    run.summary = held_out_summary;
  }
  for (std::size_t i = 0; i < cloud.size(); ++i) normals_out.set(i, {best[3 * i], best[3 * i + 1], best[3 * i + 2]});
  if (run.passes_kept > 0) {
    run.choice.params = best_candidate == detail::kHeldOutCandidate    ? held_out_params
                        : best_candidate >= detail::kFallbackCandidate ? fallback.params
                                                                       : candidates[best_candidate];
  }
  run.choice.judged = judged + detail::judged_outcome(best_candidate, run.passes_kept);
  run.choice.params.iterations = run.passes_kept;
  return run;
}

}  // namespace pnf
