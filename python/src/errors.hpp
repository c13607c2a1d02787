// pnf::Error -> the Python exception its code calls for:
//   invalid_argument, invalid_input -> ValueError     io -> OSError
//   device -> pnf.DeviceError (a RuntimeError)         cancelled -> pnf.Cancelled (a RuntimeError)
#pragma once

#include <pybind11/pybind11.h>

namespace pnf::python {

// Creates pnf.DeviceError and pnf.Cancelled in `m` and registers the translation above.
void register_errors(pybind11::module_& m);

}  // namespace pnf::python
