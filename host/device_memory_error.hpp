// The error a device throws when it refuses an allocation; the engine answers it with smaller
// chunks. Free of OpenCL so that the engine can catch it without seeing the bindings.
#pragma once

#include <string>

#include "pnf/error.hpp"

namespace pnf::detail {

class DeviceMemoryError : public Error {
 public:
  explicit DeviceMemoryError(const std::string& message) : Error(ErrorCode::device, message) {}
};

}  // namespace pnf::detail
