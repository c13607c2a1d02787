// The filters the tests run: the reference always, the OpenCL one when a device is found.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <string>

#include "pnf/error.hpp"
#include "pnf/normal_filter.hpp"

namespace pnf::test {

// The process-wide OpenCL filter (the program is built once for all tests), or nullptr with
// `why` set when no device is available. Construction failure is a test failure, not a skip,
// when PNF_DEVICE is set: then the user asked for a device.
inline NormalFilter* opencl_filter(std::string& why) {
  static std::unique_ptr<NormalFilter> filter;
  static std::string error;
  static bool tried = false;
  if (!tried) {
    tried = true;
    try {
      filter = std::make_unique<NormalFilter>(FilterOptions{Device::opencl()});
    } catch (const Error& e) {
      error = e.what();
    }
  }
  why = error;
  return filter.get();
}

// The OpenCL selector the tests' internal backends use: PNF_DEVICE's, as NormalFilter resolves it.
inline std::string opencl_selector() {
  const Device device = Device::opencl().resolved();
  return device.backend == Backend::opencl ? device.selector : std::string();
}

inline NormalFilter* reference_filter() {
  static NormalFilter filter(FilterOptions{Device::reference()});
  return &filter;
}

}  // namespace pnf::test

// In a test body: `NormalFilter* f = PNF_FILTER_OR_SKIP(backend);`
#define PNF_FILTER_OR_SKIP(backend)                                                         \
  ([&]() -> ::pnf::NormalFilter* {                                                          \
    if ((backend) == ::pnf::Backend::reference) return ::pnf::test::reference_filter();     \
    std::string why;                                                                        \
    ::pnf::NormalFilter* f = ::pnf::test::opencl_filter(why);                               \
    if (!f && std::getenv("PNF_DEVICE")) ADD_FAILURE() << "PNF_DEVICE is set but: " << why; \
    return f;                                                                               \
  }())

#define PNF_SKIP_IF_NULL(filter)                                                         \
  if (!(filter)) {                                                                       \
    std::string why;                                                                     \
    ::pnf::test::opencl_filter(why);                                                     \
    GTEST_SKIP() << "no OpenCL device (set PNF_DEVICE to make this a failure): " << why; \
  }
