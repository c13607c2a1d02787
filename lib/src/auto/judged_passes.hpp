// Internal to --auto: what one process's and a distributed run's improve_normals_auto share (the
// candidates, the pass budget and the report), so that both judge alike.
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "pnf/choose_filter_params.hpp"

namespace pnf::detail {

// The judge may run up to this many passes, or the rule's passes where more: noisy organic shapes
// gained up to 8 (teddy at 0.9 spacings of noise: 15.4 deg RMS after the rule's 2, 6.3 after 8).
constexpr int kJudgedPassBudget = 8;
// ... and a setting's passes end when this many in a row have not beaten its best so far: past
// the best, the judged RMS of the real meshes only rose (docs/auto.md).
constexpr int kJudgedPassesPastBest = 2;

// Whether a setting's judged passes end after the last of `rms_by_pass` (the input's judged RMS,
// then each pass's so far; `best_pass_here` the lowest of them, 0 the input), where a pass must
// score under `to_beat` to be kept and the setting may run `budget` passes: kJudgedPassesPastBest
// passes past its best; or, once the judged gains shrink (the last pass gained less than the one
// before), when the passes left could not reach `to_beat` even gaining as much each as the larger
// of the last two. A converging filter's gains shrink, so those passes would only be paid for;
// the larger of two, not the last, because the judged gains waver by a few tenths of a degree
// (the held-out Armadillo at 0.6% noise: 2.1, 1.9, 2.1, 2.1, and the last two passes passed the
// bar). On the real meshes and the synthetic shapes this ended the passes early on 27 of 108 and
// kept the same pass everywhere (docs/auto.md).
// With `to_beat` kNoBar (where Stein's estimate decides which pass is kept) only the passes past
// the best end them.
bool judged_passes_end(const std::vector<double>& rms_by_pass, int best_pass_here, double to_beat, int budget);
constexpr double kNoBar = -std::numeric_limits<double>::infinity();

// The passes the judge may run of `params`: the budget above, or the setting's own passes where
// more; but the line for independent errors (on_independent_errors_line) runs its own 1 or 2
// passes at most, and so does plain_averaging_setting. Averaging removes independent errors in a pass or two; past
// those, the line's wide sigma_g lets each pass smooth the surface's detail, and the judge's fits, which smooth it
// alike, agree with every pass (the crank at 0.25% noise with 10-degree tilts: 9.9 deg in, 6.7
// after one pass, 21.8 after the eight the judge kept; the cylinder at 0.5 spacings with 4-degree
// tilts: 4.0 in, 7.7 after eight). The rule's other lines keep sharp features with a tight
// sigma_g, and their extra passes were real gains the judge saw (the plane with 12-degree tilts:
// 11.7 deg in, 1.0 after eight passes, 10.3 after one), as were the passes over PCA normals,
// whose errors are correlated over the PCA neighbourhood (teddy at 0.25% noise, PCA-16: 28.4 deg
// in, 22.9 after one pass, 8.95 after eight). Where the noise hides the features
// (noise_hides_features: the rule averages plainly, up to 14 passes), its passes are as many as
// the judge's fits vouch for (passes_within_fits, `fit_points` SurfaceJudge::scored): with no
// feature term each pass diffuses the normals over its reach, and detail finer than the fits is
// smoothed by the passes and missed by the judge alike, who scores that as a gain (the cup at 20k
// points and 0.6% noise, PCA-16: 22.2 deg in, 25.9 after the judge's passes, 19.2 held to the
// fits'; docs/auto.md, "Plain averaging held to the judge's fits"). Not on smooth shapes at lesser
// noise, whose plain averaging has no detail to lose (the sphere at 0.5 spacings, PCA-16: 1.35
// deg after the judge's passes, 2.25 held to its fits of 257 points).
int judged_pass_budget(const FilterParams& params, const AutoChoice& choice, int fit_points);

// Whether the choice's estimate shows input normals whose errors are independent of the
// positions and of each other (normal_position_coupling and normal_error_correlation both under
// 0.35, normal_noise_deg from 0.6, p up to 3; on clean positions, p < 0.05, the correlation
// under 0.1), in 2000 points or more: such normals (a scanner's, a mesh's) defeat the rule's
// lines for PCA normals, so improve_normals_auto judges the rule's independent-errors setting
// beside the rule's own (docs/auto.md).
// Pure function; choose_filter_params.cpp.
bool independent_normal_errors(const AutoChoice& choice);

// Whether `params` is the rule's line for input normals with independent errors on `choice`'s
// estimate (independent_errors_setting, where independent_normal_errors holds): the rule's own
// setting or the judge's second candidate. choose_filter_params.cpp.
bool on_independent_errors_line(const AutoChoice& choice, const FilterParams& params);
// Whether the position noise is so thick (over kFeatureOffNoise area spacings) that the estimate
// cannot see the edges: the rule then averages plainly. choose_filter_params.cpp.
bool noise_hides_features(const DataEstimate& estimate);
// Whether `params` switches the feature term off (sigma_g at the rule's "off", kSigmaGOff, in
// area spacings or mean radii): plain averaging. choose_filter_params.cpp.
bool feature_term_off(const FilterParams& params);

// The setting the rule's line for input normals with errors independent of the positions gives
// `choice`'s estimate (mean radii, the choice's units, mean radius and stop rule); the choice's
// own params where that line does not apply (flat shapes with gentle creases or none, or noise
// that hides the features). choose_filter_params.cpp.
FilterParams independent_errors_setting(const AutoChoice& choice);

// The paper's sigma_f with the feature term off (plain averaging), for the line's 1 or 2 passes
// (independent_errors_line's count): on independent errors the grid's best setting on 23 of the
// real meshes' 27 tilted cases was one or two passes of plain averaging or of sigma_g 2 mean
// radii. Stein's estimate runs it beside judged_candidates (stein_candidates); the judge does
// not, as plain averaging smooths detail finer than its fits, which it cannot see.
// choose_filter_params.cpp.
FilterParams plain_averaging_setting(const AutoChoice& choice);
// The settings where Stein's estimate decides: judged_candidates, and plain_averaging_setting
// where it is not one of them.
std::vector<FilterParams> stein_candidates(const AutoChoice& choice);

// The settings the judge tries, first the rule's: and where the estimate sees input normals whose
// errors may not follow the positions (independent_normal_errors: a scanner's, a mesh's), the line
// for those too, which the rule alone tells least surely. Not for PCA normals: that line's wide
// sigma_g blurs detail finer than the judge's fits, which the judge cannot see (the camel with
// PCA-16 normals: judged better, truly 0.5% worse than its input).
std::vector<FilterParams> judged_candidates(const AutoChoice& choice);

// On clean positions, where the judge decides at the scale it chose (judge_chooses_scale), the
// judge also tries the paper's sigma_g with half its sigma_f (mean radii: 0.5 and 2). The rule
// reads an organic shape's fine detail as edges and keeps it with a tight sigma_g, whose passes
// turn the curved detail into facets (the camel, the bunny, the seahorse with PCA normals: the
// rule's first pass judged worse than the input, the input kept); this narrow, gentler setting
// follows such detail, and on clean positions the judge's fits are as fine as the spacing
// allows and tell which of the two settings gains. Chosen on the real meshes' grids (their 18
// clean PCA cases: the grid's best was sigma_f 2 mean radii on 13, with sigma_g 0.5 on 7; with
// it the best pass would come within 10% of the grid's best on 16), checked on the held-out
// models and the synthetic shapes after (docs/auto.md).
bool tries_smooth_detail(const AutoChoice& choice);
FilterParams smooth_detail_setting(const AutoChoice& choice);

// The judged RMS (degrees) a pass must stay under to be kept instead of the input, given the
// input's judged RMS and the judge's error e (judge_error_deg): sqrt(input^2 - e^2) - e.
// The judge's fits err by about e; an input whose errors are independent of the positions reads
// e in quadrature above its true error, while a filtered normal, made from the same positions,
// can share the judge's error and read up to e below its own. So a pass under this is truly
// better than the input even then. On clean positions e is small and any judged gain counts; on
// noisy ones, where the judge was fooled (the casting at 0.25% of its diagonal, exact normals:
// 0 deg in, 8.6 out), only a gain larger than the judge's own error does.
double rms_to_beat(double input_rms_deg, double error_deg);

// The fallback on noisy positions: where the judged settings keep the input and the positions
// are not clean (JudgeGeometry::quarter_allowed false: twice the noise above 0.15 spacings), one
// pass of wide averaging at the paper's sigma_f, with sigma_g at half of it (mean radii: 4 and
// 2), kept if the judge scores it under fallback_to_beat (for plane-fit input normals, the passes
// fallback_pass_budget allows, judged as the settings' are). On noisy clouds the judge's own error
// is as large as the gains of the rule's passes, so its full bar (rms_to_beat) refuses them all;
// the grid's best there is one to four passes of such averaging, and this one pass was the grid's
// most harmless setting on the real meshes' 54 noisy cases (docs/auto.md, "Against the grid, case
// by case": chosen on those grids; the synthetic cases checked it after).
bool tries_fallback(const AutoChoice& choice);
FilterParams fallback_setting(const AutoChoice& choice);
// The fallback's bar: sqrt(input^2 - e^2), the first half of rms_to_beat. The input reads e in
// quadrature above its true error (as there); one pass reaches 170-510 points (pass_reach_points)
// where the judge's fits on noisy clouds of 100k points hold 1025-4097, so it is not held to share
// the judge's whole error. Its first pass is kept only below this: with the plain comparison (below the
// input's score) 4 of the 72 noisy real and held-out cases came back worse than their input, 3 of
// them held out, and this bar was chosen after that, so the held-out sets no longer test it
// independently (docs/auto.md).
double fallback_to_beat(double input_rms_deg, double error_deg);
// judged_outcome's candidate numbers for the fallback and the narrow pass.
constexpr std::size_t kFallbackCandidate = 3;
constexpr std::size_t kNarrowPassCandidate = 4;

// The narrow pass on clean positions: where the judge chose its scale (judge_chooses_scale), the
// judged settings keep the input and the input normals are plane fits of their nearest points
// (SurfaceJudge::plane_fits: PCA normals over k points, any k), one pass of smooth_detail_setting,
// kept unless the judge scores it above the input by more than its own error (narrow_pass_to_beat).
// Such normals err by the facets and curvature their k points span; the narrow pass averages
// neighbouring fits and follows the detail (sigma_g 0.5), and the judge, whose fits see the same
// facets, cannot score that gain: on the real meshes' and held-out models' clean rows this one
// pass was truly better than the input on all 36 of the grid (PCA-16, PCA-64, tilts; the judge
// had kept the input on 8 PCA-16 rows, where it gains 6-18%), while exact normals, which the
// judge scores as it scores PCA-16 ones, are no count's plane fits and are kept (docs/auto.md,
// "The narrow pass for plane-fit normals": chosen on those grids, checked on the synthetic shapes
// after).
bool tries_narrow_pass(const AutoChoice& choice, int plane_fits);
// The narrow pass's bar: the input's score plus the judge's own error e, as the judge cannot
// tell a pass within e of the input from it.
double narrow_pass_to_beat(double input_rms_deg, double error_deg);

// The points one pass of `params` (in mean radii) reaches on `choice`'s cloud: those within the
// kernel's reach (2 sigma_f) of a surface at the estimate's area spacing. The fallback's sigma_f 4
// mean radii reaches 130 on a clean cloud of 100k points, 170-510 on the sparse and noisy ones
// (the mean radius grows with the noise).
double pass_reach_points(const AutoChoice& choice, const FilterParams& params);

// The most passes the fallback runs, for plane-fit input normals: the grid's best on the real
// meshes' noisy PCA rows was one to four passes of sigma_f 4 mean radii (sigma_g off or 2).
constexpr int kFallbackPlaneFitPasses = 4;

// The fallback's passes the judge scores (its setting's iterations): one; for input normals that
// are plane fits (`plane_fits` > 0), whose errors are shared over each fit's points and so outlast
// one pass, as many as reach together no more points than the judge's fits hold (`fit_points`,
// SurfaceJudge::scored), up to kFallbackPlaneFitPasses. k passes average about as far as one pass
// of sqrt(k) sigma_f, whose reach covers k times one pass's points (pass_reach_points); averaging
// wider than the judge's fits smooths the detail they miss, and the judge scores that as a gain.
// Chosen on the real meshes (docs/auto.md, "More fallback passes for plane fits"): fits of 257
// points on the sparse clouds hold 1.1-1.5 passes' reach, and there the passes after the first
// lost on 10 of 18 rows, one to worse than the input (the crank at 20k points and 0.25% noise,
// PCA-16: 26.28 deg in, 25.98 after one pass, 26.58 after three); fits of 1025-4097 points
// hold 3-8, and there the later passes gained on every row where they ran (the teddy at 100k
// points and 0.6% noise, PCA-64: 16.83 deg in, 12.98 after one pass, 10.42 after four; the
// fertility at 20k points and 0.6%, PCA-16: 23.81 after one, 17.14 after three).
int fallback_pass_budget(const AutoChoice& choice, int plane_fits, int fit_points);
// The passes of `params` that reach together no more points than fits of `fit_points` hold (k
// passes reach k times one pass's pass_reach_points, as above), from 1 to `most`.
int passes_within_fits(const AutoChoice& choice, const FilterParams& params, int fit_points, int most);

// The fallback a judged run tries where its settings keep the input, if any (tries_fallback or
// tries_narrow_pass): its setting (with fallback_pass_budget's passes) and bar, and its number for
// judged_outcome. `plane_fits`: SurfaceJudge::plane_fits; `fit_points`: SurfaceJudge::scored.
struct Fallback {
  FilterParams params;
  double to_beat = 0;
  std::size_t candidate = 0;  // 0: none
  int plane_fits = 0;
};
Fallback fallback_of(const AutoChoice& choice, int plane_fits, int fit_points, double input_rms_deg, double error_deg);

// The held-out check on noisy positions (held_out_planes.hpp): where the positions are noisy
// (tries_fallback) and the input normals are plane fits (SurfaceJudge::plane_fits, measured by
// prepare_judge), the passes of held_out_settings are also scored against held-out planes, and
// where the judge keeps the input (its settings and the fallback), the pass nearest those planes
// is kept if its gain over the input passes kHeldOutMinGainZ. On the real meshes' noisy PCA rows
// the judge kept the input on 16 of 36 where the grid's best gains up to half the error; its fits
// read noisy PCA input normals well under their error (the casting at 0.6% noise, PCA-16: 51.7
// deg true, 33.3 judged, its own error 17.2) and its bar then refuses every gain. Plane fits only: the
// reference planes are themselves plane fits, and blur edges and detail as such input does,
// while against scanner-like errors (tilts) the planes' blur made passes that blur edges read as
// gains (the crank at 0.6% noise, 10-degree tilts: 9.85 deg in, 23.3 out). docs/auto.md, "The
// held-out check on noisy positions".
bool tries_held_out(const AutoChoice& choice, int plane_fits);
// Its settings in the order they run, each with its pass budget as iterations: the rule's
// (judged_pass_budget; on the noisiest clouds plain averaging at about the paper's sigma_f) and
// the fallback's (up to kJudgedPassBudget passes). Plain averaging at the paper's sigma_f as a
// third never scored strictly below both on the 48 noisy PCA rows of the real meshes and
// held-out models, and cost a list build and its passes (docs/auto.md).
std::vector<FilterParams> held_out_settings(const AutoChoice& choice, int fit_points);
// Whether the judge vetoes a pass of the held-out check: where it scores the pass (`judged_deg`)
// above the input (`input_deg`). The check's score weighs errors as 1 - cos does, nearly their
// squares, and a pass that shrinks a few large errors and grows many small ones may gain there
// while the mean angle rises (the casting at 20k clean points, PCA-16: RMS 17.98 -> 17.26 deg,
// mean 9.75 -> 10.15); the judge, which scores such a pass above the input (31.2 against 31.0),
// has the last word, as over Stein's estimate.
bool judge_vetoes(double judged_deg, double input_deg);
// judged_outcome's number for the held-out check's pass.
constexpr std::size_t kHeldOutCandidate = 5;
// The held-out check's part of AutoChoice::judged: its samples and the input's disagreement
// (degrees), then each setting's by pass (judged_candidate).
std::string held_out_heading(std::size_t samples, double input_deg);

// Whether Stein's risk estimate (stein_risk.hpp) decides the passes kept: for input normals whose
// errors are independent of the positions and of each other (independent_normal_errors), whose
// noise their neighbours' normals measure (DataEstimate::normal_noise_neighbours_deg above 0).
// There the surface judge's bar is blind: its fits err by more than the gains (the camel at 0.25%
// of its diagonal, 10-degree tilts: its own error 5.0 deg, its true one about 12; the input kept,
// where one pass takes 9.85 deg to 5.9), while Stein's estimate shares no error with the filter.
bool stein_decides(const AutoChoice& choice);
// The input's noise (degrees, RMS) Stein's estimate takes: the smaller of the neighbours' and the
// chords' (DataEstimate). Each reads high by its own cause (detail finer than 16 points; position
// noise), neither low for independent errors, and a noise read low only keeps more of the input.
double stein_noise_deg(const AutoChoice& choice);

// The input normals' own noise (degrees) where it bounds the judge's error from below, else -1:
// on noisy positions where the judge decides (tries_fallback, not Stein's estimate), for input
// normals that are no count's plane fits (`plane_fits` 0: exact normals, a mesh's, a scanner's),
// whose errors are then independent of the judge's fits of the positions; stein_noise_deg (their
// neighbours' normals' reading, or the chords' where lower), -1 where the neighbours' could not
// read it (the chords alone read position noise as well).
double noise_bounding_judge_deg(const AutoChoice& choice, int plane_fits);

// The judge's error (degrees) a judged run weighs: its own error (`own_error_deg`,
// SurfaceJudge::own_error_deg: its fits' spread, a median), or more where the input shows it errs
// more. Input normals whose errors are independent of the judge's fits (`input_noise_deg` from
// noise_bounding_judge_deg; below 0: none) sit their own noise s and the judge's true error e in
// quadrature from its fits, the input's judged RMS D: e = sqrt(D^2 - s^2); and s reads high, never
// low (stein_noise_deg), so that is a floor under e. The own error, a median, misses where the fits
// of noisy positions miss detail: the seahorse at 10k points and 0.25% noise, 10-degree tilts: own
// error 7.7 deg, D 25.9, s read 20.8 (the tilts' truth 9.9), a floor of 15.5, the true error about
// 24; with the own error the judge kept 8 passes, 9.9 -> 24.2 deg (docs/auto.md). Errors shared
// by neighbours (smooth normals that are no plane fits) read low and the floor high: such input
// is kept more often, never harmed.
double judge_error_deg(double input_rms_deg, double own_error_deg, double input_noise_deg);

// Whether the judge cannot see what a pass could gain, and the input is kept without a pass: where
// the input normals' own noise bounds the judge's error (noise_bounding_judge_deg) and lies below
// that error (`error_deg`, judge_error_deg). Averaging takes out of independent errors at most
// their noise, and a pass is kept only where the judge scores it more than its error under the
// input (rms_to_beat): so where the noise is under that error, a pass it keeps gains by the judge's
// error, which on noisy positions misses detail (the crank at 0.25% of its diagonal, exact normals:
// judged 17.4 deg off with its own error read at 2.4 and the noise at 0.69; 8 passes kept, 0 ->
// 19.1 deg). Errors shared by neighbours read low too, so smooth normals that are no plane fits
// come back as they went in; plane fits (PCA) are judged as before. docs/auto.md, "Exact normals
// on noisy positions".
bool judge_cannot_see_gains(const AutoChoice& choice, int plane_fits, double error_deg);
// AutoChoice::judged where judge_cannot_see_gains keeps the input.
std::string unseen_gains_judged(const AutoChoice& choice, double input_rms_deg, double own_error_deg, double error_deg);

// Whether the judge's fits are too wide to vouch for a pass: where they hold more than half the
// cloud's points (`fit_points`: SurfaceJudge::scored, of `cloud_points`). No more than half a
// closed surface is a height field over one plane (a sphere's hemisphere holds half), so such fits
// follow the model's overall shape, not the surface near their sample, and passes that smooth the
// normals toward that shape score as gains (the seahorse at 6k points and 0.6% noise, fits of 4097
// of its 6000 points: 14 passes kept, its exact normals 0 -> 47.4 deg, its tilts 9.9 -> 47.6). There
// the judge keeps no pass of its own: the held-out check decides where it runs (tries_held_out: its
// planes are fitted to the other half's nearest points, not to half the cloud), else the input is
// kept without a pass. Where Stein's estimate decides, the judge only vetoes, and this does not
// apply (docs/auto.md, "Judge's fits that hold half the cloud").
bool judge_fits_too_wide(int fit_points, std::size_t cloud_points);
// AutoChoice::judged's first part where judge_fits_too_wide holds (in place of judged_heading).
std::string too_wide_heading(std::size_t samples, int fit_points, std::size_t cloud_points);

// What the judge measures of the input before any pass, as `choice` needs it: its scale
// (choose_scale) where it chooses one, else whether the input normals are plane fits where the
// held-out check may need it (the positions are noisy); `input`: N by 3, unit.
class SurfaceJudge;
void prepare_judge(SurfaceJudge& judge, const AutoChoice& choice, const double* input);

// Whether the judge chooses its scale (SurfaceJudge::choose_scale: the input fitted at both) before
// judging: where the positions allow the quarter (JudgeGeometry::quarter_allowed) and the judge
// decides. Where Stein's estimate decides, the judge only vetoes its pass, scored against the input
// at the whole neighbourhood: the quarter changed no outcome on clean clouds (docs/auto.md,
// "Where --auto still misses the grid"), and its fit of the input is saved (0-0.05 s a run on
// 100k points, docs/auto.md "Time").
bool judge_chooses_scale(const AutoChoice& choice);

// AutoChoice::judged, in three parts: the judge and the input's RMS, with the judge's own error and
// the error weighed (judge_error_deg), which sets the bar; each setting's RMS by pass; the outcome.
// `under_support`: SurfaceJudge::under_support (0: not said).
std::string judged_heading(double input_rms_deg, double own_error_deg, double error_deg, std::size_t samples,
                           int fit_points, int under_support);
std::string judged_candidate(std::size_t candidate, const FilterParams& params, const std::vector<double>& rms_by_pass);
// ... where judged_pass_budget held a setting to fewer passes than it asks (the rule's "up to 14
// passes" where the noise hides the features), by how many; else empty.
std::string judged_budget_note(const FilterParams& setting, int budget);
std::string judged_outcome(std::size_t best_candidate, int passes_kept);
// ... a fallback's RMS by pass and the bar it had to beat.
std::string judged_fallback(const Fallback& fallback, const std::vector<double>& rms_by_pass);
// ... and where Stein's estimate decides (improve_normals_auto's stein_run): the judge's RMS of
// the input and of the pass of lowest estimate (0: none), which must not score above the input;
// then the estimate's noise, each setting's estimates by pass (judged_candidate) and the outcome.
std::string stein_judged(double input_rms_deg, double kept_rms_deg);
std::string stein_heading(const AutoChoice& choice);

}  // namespace pnf::detail
