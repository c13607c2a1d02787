#include "pnf/filter_params.hpp"

#include <cmath>
#include <sstream>

#include "pnf/error.hpp"

namespace pnf {
namespace {

void require(bool ok, const char* field, double value, const char* rule) {
  if (ok) return;
  std::ostringstream msg;
  msg << "invalid filter parameter " << field << " = " << value << ": must be " << rule;
  throw Error(ErrorCode::invalid_argument, msg.str());
}

}  // namespace

const char* to_string(Units units) { return units == Units::radius ? "radius" : "absolute"; }

void FilterParams::validate() const {
  require(std::isfinite(sigma_f) && sigma_f > 0, "sigma_f", sigma_f, "finite and > 0");
  require(std::isfinite(sigma_g) && sigma_g > 0, "sigma_g", sigma_g, "finite and > 0");
  require(iterations >= 0, "iterations", iterations, ">= 0");
  require(std::isfinite(stop_change_deg) && stop_change_deg >= 0, "stop_change_deg", stop_change_deg,
          "finite and >= 0 (0: no stop rule)");
  require(std::isfinite(mean_radius) && mean_radius >= 0, "mean_radius", mean_radius,
          "finite and >= 0 (0: from the data)");
  require(units == Units::radius || units == Units::absolute, "units", static_cast<int>(units),
          "Units::radius or Units::absolute");
}

}  // namespace pnf
