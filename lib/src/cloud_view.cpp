#include "pnf/cloud_view.hpp"

namespace pnf {

const char* to_string(ScalarType type) { return type == ScalarType::float32 ? "float32" : "float64"; }

}  // namespace pnf
