#include "progress_text.hpp"

#include <algorithm>

namespace pnf::cli {

ProgressText progress_text(const PassProgress& p) {
  const double fraction = std::clamp(p.fraction, 0.0, 1.0);
  ProgressText text;
  char label[48];
  if (p.stage == ProgressStage::pass) {
    text.done = p.passes > 0 ? double(p.pass) / p.passes : 1.0;
    std::snprintf(label, sizeof label, "pass %d/%d", p.pass, p.passes);
  } else if (p.stage == ProgressStage::filtering) {
    text.done = p.passes > 0 ? (p.pass + fraction) / p.passes : 1.0;
    std::snprintf(label, sizeof label, "pass %d/%d", p.pass + 1, p.passes);
  } else {
    text.done = fraction;
    std::snprintf(label, sizeof label, "%s %3.0f%%", to_string(p.stage), 100 * fraction);
  }
  text.done = std::min(text.done, 1.0);
  text.label = label;
  return text;
}

ProgressLines::ProgressLines(std::FILE* out, double interval_seconds)
    : out_(out), interval_(interval_seconds), start_(std::chrono::steady_clock::now()), last_(start_) {}

void ProgressLines::operator()(const PassProgress& p) {
  const auto now = std::chrono::steady_clock::now();
  if (std::chrono::duration<double>(now - last_).count() < interval_) return;
  last_ = now;
  const ProgressText text = progress_text(p);
  // Passes also say how far the whole run of passes is; the other stages' label has its share.
  if (p.stage == ProgressStage::pass || p.stage == ProgressStage::filtering) {
    std::fprintf(out_, "pnf: %s, %.0f%% of the passes (%.1f s)\n", text.label.c_str(), 100 * text.done,
                 std::chrono::duration<double>(now - start_).count());
  } else {
    std::fprintf(out_, "pnf: %s (%.1f s)\n", text.label.c_str(), std::chrono::duration<double>(now - start_).count());
  }
  std::fflush(out_);
}

}  // namespace pnf::cli
