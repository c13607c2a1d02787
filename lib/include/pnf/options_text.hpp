// pnf::parse_units, pnf::parse_backend_and_device — the text forms of the filter's units and of
// where it runs, read once here so that the CLI (--units, --backend, --device) and Python
// (units=, backend=, device=) accept and refuse the same words with the same messages.
#pragma once

#include <string>

#include "pnf/device.hpp"
#include "pnf/filter_params.hpp"

namespace pnf {

// "radius" or "absolute" (what to_string(Units) writes), exactly. Anything else throws
// pnf::Error(invalid_argument) naming the value and the two words. Thread safety: a pure function.
Units parse_units(const std::string& text);

// The Device for a backend name and a device text:
//   backend "opencl":    `device` as Device::parse reads it ("" means PNF_DEVICE, then the default
//                        rule; "reference" is the reference backend, as it is for PNF_DEVICE).
//   backend "reference": the reference backend; `device` must be "" or "reference", since an
//                        OpenCL selector beside it would be ignored: any other device throws
//                        pnf::Error(invalid_argument) naming both.
// Any other backend throws pnf::Error(invalid_argument) naming it. Names are case-sensitive for
// the backend (as the CLI's choices), case-insensitive for the device (as Device::parse).
// Thread safety: a pure function (PNF_DEVICE is read later, by Device::resolved()).
Device parse_backend_and_device(const std::string& backend, const std::string& device);

}  // namespace pnf
