// Template part of cl_runtime.hpp.
#pragma once

#include "device_memory_error.hpp"
#include "pnf/error.hpp"

namespace pnf::detail {

// True for the codes a device gives when it has no room for a buffer or its work.
inline bool is_allocation_failure(cl_int code) {
  return code == CL_MEM_OBJECT_ALLOCATION_FAILURE || code == CL_OUT_OF_RESOURCES || code == CL_OUT_OF_HOST_MEMORY ||
         code == CL_INVALID_BUFFER_SIZE;
}

template <typename Body>
auto with_cl_errors(const std::string& device_name, Body&& body) -> decltype(body()) {
  try {
    return body();
  } catch (const cl::Error& e) {
    const std::string what = std::string("OpenCL call ") + e.what() + " failed with " + cl_error_name(e.err()) +
                             " on device '" + device_name + "'";
    if (is_allocation_failure(e.err())) throw DeviceMemoryError(what);
    throw Error(ErrorCode::device, what);
  }
}

}  // namespace pnf::detail
