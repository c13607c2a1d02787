// The parts of the module, each in its own file.
#pragma once

#include <pybind11/pybind11.h>

namespace pnf::python {

void bind_point_file(pybind11::module_& m);

}  // namespace pnf::python
