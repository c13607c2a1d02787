#include <gtest/gtest.h>

#include <cstdlib>

#include "cl_runtime.hpp"
#include "device_select.hpp"
#include "pnf/device.hpp"
#include "pnf/error.hpp"
#include "pnf/normal_filter.hpp"

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
  EXPECT_EQ(choose_device(devices, "pocl"), 0);  // SPEC's example: found through the platform vendor
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
    pnf::NormalFilter filter(pnf::FilterOptions{pnf::Backend::opencl, "no-such-device-xyz"});
    FAIL() << "constructed a filter on a device that does not exist";
  } catch (const pnf::Error& e) {
    EXPECT_EQ(e.code(), pnf::ErrorCode::device);
    EXPECT_NE(std::string(e.what()).find("'no-such-device-xyz'"), std::string::npos) << e.what();
  }
}

TEST(Devices, ListMarksTheSelectedDevice) {
  std::vector<DeviceInfo> devices = pnf::list_devices("cpu");
  if (devices.empty()) {
    if (std::getenv("PNF_DEVICE")) FAIL() << "PNF_DEVICE is set but no OpenCL device was found";
    GTEST_SKIP() << "no OpenCL platform on this machine";
  }
  int selected = 0;
  for (const DeviceInfo& d : devices) selected += d.selected;
  EXPECT_LE(selected, 1);
  for (const DeviceInfo& d : devices) {
    if (d.selected) EXPECT_EQ(d.type, "cpu");
  }
}

}  // namespace

namespace {

TEST(Devices, AKernelThatFailsToBuildShowsItsBuildLog) {
  std::vector<DeviceInfo> devices = pnf::list_devices();
  if (devices.empty()) {
    if (std::getenv("PNF_DEVICE")) FAIL() << "PNF_DEVICE is set but no OpenCL device was found";
    GTEST_SKIP() << "no OpenCL platform on this machine";
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
