#include "pnf/options_text.hpp"

#include "pnf/error.hpp"

namespace pnf {

Units parse_units(const std::string& text) {
  for (const Units units : {Units::radius, Units::absolute}) {
    if (text == to_string(units)) return units;
  }
  throw Error(ErrorCode::invalid_argument, "units '" + text + "': must be 'radius' or 'absolute'");
}

Device parse_backend_and_device(const std::string& backend, const std::string& device) {
  if (backend == to_string(Backend::opencl)) return Device::parse(device);
  if (backend != to_string(Backend::reference)) {
    throw Error(ErrorCode::invalid_argument, "backend '" + backend + "': must be 'opencl' or 'reference'");
  }
  // Refused rather than ignored: the caller asked for an OpenCL device and would not get it.
  if (!device.empty() && Device::parse(device) != Device::reference()) {
    throw Error(ErrorCode::invalid_argument, "backend 'reference' runs on the CPU without OpenCL, but device '" +
                                                 device + "' is an OpenCL device: give one of the two");
  }
  return Device::reference();
}

}  // namespace pnf
