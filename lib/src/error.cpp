#include "pnf/error.hpp"

namespace pnf {

const char* to_string(ErrorCode code) {
  switch (code) {
    case ErrorCode::invalid_argument: return "invalid_argument";
    case ErrorCode::invalid_input: return "invalid_input";
    case ErrorCode::io: return "io";
    case ErrorCode::device: return "device";
    case ErrorCode::cancelled: return "cancelled";
  }
  return "unknown";
}

}  // namespace pnf
