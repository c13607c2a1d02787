// The filters the tests run: the reference always, the OpenCL one when a device is found.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <string>

#include "pnf/device.hpp"
#include "pnf/error.hpp"
#include "pnf/normal_filter.hpp"

namespace pnf::test {

// Whether a test that needs OpenCL may skip: only when this machine has no OpenCL device at all
// and PNF_DEVICE is unset. A device that exists but fails, or one asked for by PNF_DEVICE and not
// found, is a failure.
inline bool may_skip_without_opencl() { return !std::getenv("PNF_DEVICE") && list_devices().empty(); }

// The process-wide OpenCL filter (the program is built once for all tests), or nullptr with
// `why` set when it could not be made (PNF_OPENCL_OR_SKIP then skips or fails).
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

// In a test body, where OpenCL could not be set up (`why`): skips when no OpenCL device exists
// and PNF_DEVICE is unset, and says so; fails otherwise.
#define PNF_OPENCL_OR_SKIP(why)                                                                               \
  do {                                                                                                        \
    if (::pnf::test::may_skip_without_opencl()) {                                                             \
      GTEST_SKIP() << "no OpenCL device on this machine and PNF_DEVICE unset (set it to make this a "         \
                      "failure): "                                                                            \
                   << (why);                                                                                  \
    }                                                                                                         \
    FAIL() << "OpenCL could not be set up although "                                                          \
           << (std::getenv("PNF_DEVICE") ? "PNF_DEVICE is set" : "this machine has an OpenCL device") << ": " \
           << (why);                                                                                          \
  } while (false)

// In a test body: `NormalFilter* f = PNF_FILTER_OR_SKIP(backend);` then PNF_SKIP_IF_NULL(f).
#define PNF_FILTER_OR_SKIP(backend)                                                     \
  ([&]() -> ::pnf::NormalFilter* {                                                      \
    if ((backend) == ::pnf::Backend::reference) return ::pnf::test::reference_filter(); \
    std::string why;                                                                    \
    return ::pnf::test::opencl_filter(why);                                             \
  }())

#define PNF_SKIP_IF_NULL(filter)     \
  if (!(filter)) {                   \
    std::string why;                 \
    ::pnf::test::opencl_filter(why); \
    PNF_OPENCL_OR_SKIP(why);         \
  }
