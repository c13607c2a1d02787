#include <gtest/gtest.h>

#include <cstdlib>

#include "cl_runtime.hpp"
#include "device_select.hpp"
#include "pnf/device.hpp"
#include "pnf/error.hpp"
#include "pnf/normal_filter.hpp"
#include "test_backends.hpp"

namespace {

using pnf::DeviceInfo;
using pnf::detail::choose_device;

std::vector<DeviceInfo> fake_devices() {
  auto make = [](int p, int d, const char* platform, const char* vendor, const char* name, const char* type) {
    DeviceInfo i;
    i.platform_index = p;
    i.device_index = d;
    i.platform_name = platform;
    i.platform_vendor = vendor;
    i.device_name = name;
    i.device_vendor = vendor;
    i.type = type;
    return i;
  };
  // Names and vendors as the drivers report them.
  return {make(0, 0, "Portable Computing Language", "The pocl project", "pthread-skylake", "cpu"),
          make(1, 0, "NVIDIA CUDA", "NVIDIA Corporation", "NVIDIA H100", "gpu"),
          make(1, 1, "NVIDIA CUDA", "NVIDIA Corporation", "NVIDIA H200", "gpu"),
          make(2, 0, "FPGA SDK", "Board Maker", "Board", "accelerator")};
}

TEST(DeviceSelect, SelectorsFollowSpec) {
  auto devices = fake_devices();
  EXPECT_EQ(choose_device(devices, ""), 1);  // first GPU
  EXPECT_EQ(choose_device(devices, "cpu"), 0);
  EXPECT_EQ(choose_device(devices, "GPU"), 1);
  EXPECT_EQ(choose_device(devices, "accelerator"), 3);
  EXPECT_EQ(choose_device(devices, "1:1"), 2);
  EXPECT_EQ(choose_device(devices, "pocl"), 0);  // docs/method.md's example: found through the platform vendor
  EXPECT_EQ(choose_device(devices, "portable"), 0);
  EXPECT_EQ(choose_device(devices, "h200"), 2);
  EXPECT_EQ(choose_device(devices, "nvidia"), 1);
  EXPECT_EQ(choose_device(devices, "3:0"), -1);
  EXPECT_EQ(choose_device(devices, "vulkan"), -1);
}

TEST(DeviceSelect, DefaultFallsBackToCpuWithoutGpu) {
  auto devices = fake_devices();
  devices.erase(devices.begin() + 1, devices.begin() + 3);
  EXPECT_EQ(choose_device(devices, ""), 0);
  devices.erase(devices.begin());
  EXPECT_EQ(choose_device(devices, ""), -1);  // an accelerator alone is not a default
}

TEST(DeviceSelect, NoMatchMessageListsEveryDevice) {
  std::string msg = pnf::detail::no_device_message(fake_devices(), "vulkan");
  EXPECT_NE(msg.find("no OpenCL device matches 'vulkan'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("[0:0] cpu 'pthread-skylake'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("[1:1] gpu 'NVIDIA H200'"), std::string::npos) << msg;
  EXPECT_NE(pnf::detail::no_device_message({}, "").find("no OpenCL platform"), std::string::npos);
}

TEST(Devices, UnmatchedSelectorIsAClearError) {
  try {
    pnf::NormalFilter filter(pnf::FilterOptions{pnf::Device::opencl("no-such-device-xyz")});
    FAIL() << "constructed a filter on a device that does not exist";
  } catch (const pnf::Error& e) {
    EXPECT_EQ(e.code(), pnf::ErrorCode::device);
    EXPECT_NE(std::string(e.what()).find("'no-such-device-xyz'"), std::string::npos) << e.what();
  }
}

TEST(Devices, ListMarksTheSelectedDevice) {
  std::vector<DeviceInfo> devices = pnf::list_devices("cpu");
  if (devices.empty()) {
    PNF_OPENCL_OR_SKIP("no OpenCL platform");
  }
  // "cpu" selects the first CPU device: exactly one where there is one, none where there is not.
  int selected = 0, cpus = 0;
  for (const DeviceInfo& d : devices) {
    selected += d.selected;
    cpus += d.type == "cpu";
    if (d.selected) EXPECT_EQ(d.type, "cpu");
  }
  EXPECT_EQ(selected, cpus > 0 ? 1 : 0);
}

}  // namespace

namespace {

TEST(Devices, AKernelThatFailsToBuildShowsItsBuildLog) {
  std::vector<DeviceInfo> devices = pnf::list_devices();
  if (devices.empty()) {
    PNF_OPENCL_OR_SKIP("no OpenCL platform");
  }
  pnf::detail::ClRuntime runtime("");
  try {
    runtime.kernel("filter.cl", "pnf_filter_pass", "-cl-std=CL1.2 -DPNF_LANES=3");  // #error in pnf_common.h
    FAIL() << "the build succeeded";
  } catch (const pnf::Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.code(), pnf::ErrorCode::device);
    EXPECT_NE(what.find("options '-cl-std=CL1.2 -DPNF_LANES=3'"), std::string::npos) << what;
    EXPECT_NE(what.find("build log"), std::string::npos) << what;
    EXPECT_NE(what.find("PNF_LANES must be 1, 4, 8 or 16"), std::string::npos) << what;
    EXPECT_NE(what.find("pnf_common.h"), std::string::npos) << "the #line markers name the real file: " << what;
  }
}

}  // namespace

namespace {

TEST(DeviceValue, ParsesEveryFormAndPrintsItBack) {
  using pnf::Backend;
  using pnf::Device;
  EXPECT_EQ(Device::parse("reference"), Device::reference());
  EXPECT_EQ(Device::parse("Reference"), Device::reference());
  EXPECT_EQ(Device::parse("opencl"), Device::opencl());
  EXPECT_EQ(Device::parse(""), Device::opencl());
  EXPECT_EQ(Device::parse("opencl:gpu"), Device::opencl("gpu"));
  EXPECT_EQ(Device::parse("opencl:1:0"), Device::opencl("1:0"));
  EXPECT_EQ(Device::parse("gpu"), Device::opencl("gpu"));  // a bare selector, as PNF_DEVICE has always taken
  EXPECT_EQ(Device::parse("1:0"), Device::opencl("1:0"));
  EXPECT_EQ(Device::parse("pocl"), Device::opencl("pocl"));
  for (const char* text : {"reference", "opencl", "opencl:gpu", "opencl:1:0", "opencl:NVIDIA H200"}) {
    EXPECT_EQ(Device::parse(text).to_string(), text);
    EXPECT_EQ(Device::parse(Device::parse(text).to_string()), Device::parse(text)) << text;
  }
  try {
    Device::parse("opencl:");
    FAIL() << "no error";
  } catch (const pnf::Error& e) {
    EXPECT_EQ(e.code(), pnf::ErrorCode::invalid_argument);
    EXPECT_NE(std::string(e.what()).find("no selector after 'opencl:'"), std::string::npos) << e.what();
  }
}

TEST(DeviceValue, AnEmptySelectorResolvesThroughTheEnvironment) {
  const char* saved = std::getenv(pnf::kDeviceEnvironmentVariable);
  const std::string restore = saved ? saved : "";
  setenv(pnf::kDeviceEnvironmentVariable, "reference", 1);
  EXPECT_EQ(pnf::Device::opencl().resolved(), pnf::Device::reference());
  setenv(pnf::kDeviceEnvironmentVariable, "opencl:gpu", 1);
  EXPECT_EQ(pnf::Device::opencl().resolved(), pnf::Device::opencl("gpu"));
  EXPECT_EQ(pnf::Device::opencl("cpu").resolved(), pnf::Device::opencl("cpu")) << "a selector in code wins";
  EXPECT_EQ(pnf::Device::reference().resolved(), pnf::Device::reference());
  unsetenv(pnf::kDeviceEnvironmentVariable);
  EXPECT_EQ(pnf::Device::opencl().resolved(), pnf::Device::opencl());
  if (saved) setenv(pnf::kDeviceEnvironmentVariable, restore.c_str(), 1);
}

TEST(FilterOptionsValidate, NamesTheFieldAndTheValue) {
  auto message = [](const pnf::FilterOptions& options) {
    try {
      options.validate();
    } catch (const pnf::Error& e) {
      EXPECT_EQ(e.code(), pnf::ErrorCode::invalid_argument);
      return std::string(e.what());
    }
    return std::string("(valid)");
  };
  EXPECT_EQ(message({}), "(valid)");
  pnf::FilterOptions o;
  o.memory.budget_bytes = 0;
  EXPECT_EQ(message(o), "invalid filter option memory.budget_bytes = 0: must be > 0");
  o = {};
  o.memory.max_neighbour_pairs = 0;
  EXPECT_EQ(message(o), "invalid filter option memory.max_neighbour_pairs = 0: must be > 0");
  o = {};
  o.reference_threads = -2;
  EXPECT_EQ(message(o), "invalid filter option reference_threads = -2: must be >= 0 (0: all cores)");
  // The constructor validates too.
  EXPECT_THROW(pnf::NormalFilter{o}, pnf::Error);
}

TEST(ClRuntime, IsMoveOnly) {
  static_assert(!std::is_copy_constructible_v<pnf::detail::ClRuntime>);
  static_assert(!std::is_copy_assignable_v<pnf::detail::ClRuntime>);
  static_assert(std::is_move_constructible_v<pnf::detail::ClRuntime>);
}

TEST(WithClErrors, AllocationCodesBecomeTheDeviceMemoryErrorAndOthersADeviceError) {
  for (cl_int code :
       {CL_MEM_OBJECT_ALLOCATION_FAILURE, CL_OUT_OF_RESOURCES, CL_OUT_OF_HOST_MEMORY, CL_INVALID_BUFFER_SIZE}) {
    EXPECT_THROW(pnf::detail::with_cl_errors("dev", [&] { throw cl::Error(code, "clCreateBuffer"); }),
                 pnf::detail::DeviceMemoryError)
        << pnf::detail::cl_error_name(code);
  }
  try {
    pnf::detail::with_cl_errors("dev", [] { throw cl::Error(CL_INVALID_KERNEL_ARGS, "clEnqueueNDRangeKernel"); });
    FAIL() << "no error";
  } catch (const pnf::detail::DeviceMemoryError&) {
    FAIL() << "not an allocation failure";
  } catch (const pnf::Error& e) {
    EXPECT_EQ(e.code(), pnf::ErrorCode::device);
    EXPECT_EQ(std::string(e.what()),
              "OpenCL call clEnqueueNDRangeKernel failed with CL_INVALID_KERNEL_ARGS on device 'dev'");
  }
}

}  // namespace
