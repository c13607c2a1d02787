// Template part of cl_runtime.hpp.
#pragma once

#include "pnf/error.hpp"

namespace pnf::detail {

template <typename Body>
auto with_cl_errors(const std::string& device_name, Body&& body) -> decltype(body()) {
  try {
    return body();
  } catch (const cl::Error& e) {
    throw Error(ErrorCode::device, std::string("OpenCL call ") + e.what() + " failed with " + cl_error_name(e.err()) +
                                       " on device '" + device_name + "'");
  }
}

}  // namespace pnf::detail
