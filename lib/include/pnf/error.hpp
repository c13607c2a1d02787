// pnf::Error — the one exception type the library throws.
#pragma once

#include <stdexcept>
#include <string>

namespace pnf {

// What kind of failure an Error reports; the CLI maps each to its own exit code.
enum class ErrorCode {
  invalid_argument,  // a parameter is out of range (sigma <= 0, negative iterations, ...)
  invalid_input,     // the data is unusable (NaN coordinate, zero normal, malformed file)
  io,                // a file could not be opened, read or written
  device,            // no OpenCL platform or device, a failed kernel build or launch
  cancelled,         // the progress callback asked to stop
};

// Returns a stable lower-case name for `code` ("invalid_argument", ...).
const char* to_string(ErrorCode code);

// Thrown by every pnf function on failure. what() is one line that names what went wrong and
// where (the parameter, the file and vertex, the device and call).
class Error : public std::runtime_error {
 public:
  Error(ErrorCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
  ErrorCode code() const noexcept { return code_; }

 private:
  ErrorCode code_;
};

}  // namespace pnf
