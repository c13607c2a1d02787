// pnf::improve_normals_auto — `pnf filter --auto` in one call: the rule's setting
// (pnf/choose_filter_params.hpp), its passes judged against the surface fitted to the positions,
// the best kept (docs/auto.md).
#pragma once

#include <vector>

#include "pnf/choose_filter_params.hpp"
#include "pnf/cloud_view.hpp"
#include "pnf/filter_summary.hpp"
#include "pnf/normal_filter.hpp"
#include "pnf/progress.hpp"

namespace pnf {

// What improve_normals_auto did.
struct AutoRun {
  // The choice, with params.iterations the passes kept (0: the input normals were kept).
  AutoChoice choice;
  FilterSummary summary;  // the filter's run (passes_run: the passes tried)
  int passes_kept = 0;
  // What the passes kept were chosen on, after each pass run (every setting's in turn): the
  // judge's RMS angle (degrees) to the surface fitted to the positions; or, where the input
  // normals' errors are independent and Stein's estimate decides (docs/auto.md), its estimate
  // of the RMS angle to the truth. Empty when no pass ran or no fit was smooth enough to judge.
  std::vector<double> judged_rms_deg;
};

// `pnf filter --auto` in one call: choose_filter_params(cloud), then the chosen
// passes, each judged against the normals of local quadric fits to the positions (a jet fit of
// order 2, without the input normals) at the samples where the fit is smooth; the pass whose
// normals agree best with them is kept, and the input normals (normalised) when none beats them,
// so on the judged parts of the surface --auto never returns normals further from the positions'
// surface than its input (docs/auto.md). On noisy positions where no pass beats them, one pass
// of wide averaging is judged too, against the input's score less the judge's own error in
// quadrature (docs/auto.md, "The judged fallback on noisy positions"); on clean positions a
// narrow, gentler setting (sigma_f 2, sigma_g 0.5 mean radii) is judged beside the rule's
// (docs/auto.md, "The judge's second setting on clean positions"). On noisy positions, input
// normals that are no plane fits of their neighbours and whose own noise is under the judge's
// own error are kept without a pass (docs/auto.md, "Exact normals on noisy positions"). Writes
// N unit normals into normals_out (N rows; it may be the cloud's own normals view). A
// stop_change_deg >= 0 replaces the rule's stop rule (0: off). Throws as choose_filter_params
// and NormalFilter::run do.
AutoRun improve_normals_auto(const CloudView& cloud, MutableVec3ArrayView normals_out, NormalFilter& filter,
                             const ProgressCallback& progress = {}, double stop_change_deg = -1);

}  // namespace pnf
