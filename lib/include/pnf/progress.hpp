// pnf::PassProgress and pnf::ProgressCallback — progress and cancellation of the library's long
// calls (NormalFilter::run, improve_normals, estimate_normals).
#pragma once

#include <functional>

namespace pnf {

// Which long step a progress report is about.
enum class ProgressStage {
  // A filter pass has finished: pass, passes and seconds (that pass's wall time) are set.
  pass,
  // Building neighbour lists: the filter's count and fill (in chunked runs, each chunk's fill
  // again in every pass), estimate_normals' k-nearest search. pass is the passes finished so far.
  lists,
  // estimate_normals' plane fits and orientation.
  estimate,
  // Within a filter pass: pass is the passes finished so far, fraction the share of this pass's
  // points done, seconds the pass's time so far (about every 0.2 s).
  filtering,
};

// What a progress callback is told. Reported after each pass (stage pass, fraction 1), and about
// every 0.2 s during the other stages and within a pass (stage filtering); always on the thread that called run() or
// estimate_normals(), never concurrently. Return false from the callback to cancel the run: the
// library's worker threads stop at their next block of work, the call throws
// pnf::Error(cancelled) and writes nothing. Fields added after pass, passes and seconds have
// defaults, so PassProgress{pass, passes, seconds} still means a finished pass.
struct PassProgress {
  int pass = 0;        // stage pass: 1-based pass just finished; other stages: passes finished so far
  int passes = 0;      // total passes (0 in estimate_normals)
  double seconds = 0;  // stage pass: that pass's wall time; other stages: time spent in the stage so far
  ProgressStage stage = ProgressStage::pass;
  double fraction = 1;  // share of this stage's work done, in [0, 1]; 1 for a finished pass
};
const char* to_string(ProgressStage stage);  // "pass", "lists", "estimate", "filtering"
using ProgressCallback = std::function<bool(const PassProgress&)>;

}  // namespace pnf
