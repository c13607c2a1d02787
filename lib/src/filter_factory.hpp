// Internal: NormalFilters with kernel tuning that the public options leave to the device type.
// The bench and the parity tests use it to time and check every lane width.
#pragma once

#include "pnf/normal_filter.hpp"

namespace pnf::detail {

struct FilterFactory {
  // A filter whose OpenCL kernel takes `lanes` neighbours per vector step (1, 4, 8 or 16; 0: the
  // device type's default, as NormalFilter(options) picks). Ignored by the reference backend.
  static NormalFilter with_lanes(const FilterOptions& options, int lanes);
};

}  // namespace pnf::detail
