#include "pnf/progress.hpp"

namespace pnf {

const char* to_string(ProgressStage stage) {
  switch (stage) {
    case ProgressStage::pass: return "pass";
    case ProgressStage::lists: return "lists";
    case ProgressStage::estimate: return "estimate";
    case ProgressStage::filtering: return "filtering";
  }
  return "unknown";
}

}  // namespace pnf
