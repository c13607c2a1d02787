// What the pnf command shows of a run's progress: the label and share done that the terminal's
// bar draws, and the lines written instead where stderr is not a terminal (a batch log, or
// rank 0 under mpirun, whose stderr is a pipe to mpirun).
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

#include "pnf/progress.hpp"

namespace pnf::cli {

// The share of the whole stage done (for passes: of all passes, within a pass too) and its label:
// "pass 3/8", "lists  45%", "estimate  80%".
struct ProgressText {
  double done = 0;
  std::string label;
};
ProgressText progress_text(const PassProgress& p);

// Writes one line "pnf: <label> <percent> (<seconds since the start> s)" to `out` at a report
// that comes at least `interval_seconds` after the start or the last line, so that short runs
// print nothing and a long one a line every interval.
class ProgressLines {
 public:
  ProgressLines(std::FILE* out, double interval_seconds);
  void operator()(const PassProgress& p);

 private:
  std::FILE* out_;
  double interval_;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace pnf::cli
