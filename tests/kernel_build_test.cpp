// The kernels compile without a warning on the device in use, at every lane count the host can
// ask for. pnf builds them with -w (lib/src/opencl_backend.cpp), so that no OpenCL compiler
// prints to the user's terminal (clang writes its "N warnings generated." line to stderr itself,
// outside the build log, on every rank under mpirun); this test builds them without -w, so a
// warning still shows up here, with the build log, instead of being hidden for good.
#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "cl_runtime.hpp"
#include "kernel_source.hpp"
#include "pnf/device.hpp"
#include "pnf/error.hpp"
#include "test_backends.hpp"

namespace pnf::test {
namespace {

TEST(KernelBuild, FilterKernelCompilesWithoutWarnings) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(Backend::opencl);
  PNF_SKIP_IF_NULL(filter);
  const Device device = Device::opencl().resolved();
  if (device.backend != Backend::opencl) GTEST_SKIP() << "PNF_DEVICE asks for the reference";
  detail::ClRuntime runtime(device.selector);
  const std::string source = detail::kernel_source("filter.cl");
  // A diagnostic on a line of our files ("pnf_common.h:145:17: warning: ..."), as clang writes
  // it; notes a driver adds about its own choices (NVIDIA's "Warning: Function ... is a kernel")
  // point at no line and are not ours to fix.
  const std::regex diagnostic(R"([A-Za-z_.]+:[0-9]+:[0-9]+: warning:)");
  for (const int lanes : {1, 4, 8, 16}) {
    const std::string options = "-cl-std=CL1.2 -DPNF_LANES=" + std::to_string(lanes);
    cl::Program program(runtime.context(), source);
    try {
      program.build({runtime.device()}, options.c_str());
    } catch (const cl::Error& e) {
      FAIL() << options << ": " << detail::cl_error_name(e.err()) << "\n"
             << program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(runtime.device());
    }
    const std::string log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(runtime.device());
    EXPECT_FALSE(std::regex_search(log, diagnostic)) << options << " on " << runtime.info().device_name << ":\n" << log;
  }
}

}  // namespace
}  // namespace pnf::test
