#include "errors.hpp"

#include "pnf/error.hpp"

namespace pnf::python {
namespace {

// Owned by the module (its attributes); these are borrowed for the translator.
PyObject* device_error = nullptr;
PyObject* cancelled_error = nullptr;

PyObject* new_exception(pybind11::module_& m, const char* name, const char* doc) {
  const std::string qualified = std::string("pnf.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, PyExc_RuntimeError, nullptr);
  if (type == nullptr) throw pybind11::error_already_set();
  // The module takes its own reference; ours stays for the translator for the life of the process.
  m.add_object(name, pybind11::handle(type));
  return type;
}

}  // namespace

void register_errors(pybind11::module_& m) {
  device_error = new_exception(m, "DeviceError",
                               "No OpenCL platform or no device matching the selector (the message lists the "
                               "devices found), or a kernel that failed to build or run.");
  cancelled_error = new_exception(m, "Cancelled", "The progress callback returned False.");
  pybind11::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      PyObject* type = PyExc_RuntimeError;
      switch (e.code()) {
        case ErrorCode::invalid_argument:
        case ErrorCode::invalid_input: type = PyExc_ValueError; break;
        case ErrorCode::io: type = PyExc_OSError; break;
        case ErrorCode::device: type = device_error; break;
        case ErrorCode::cancelled: type = cancelled_error; break;
      }
      PyErr_SetString(type, e.what());
    }
  });
}

}  // namespace pnf::python
