// pnf::list_devices — the OpenCL devices pnf can run on, and which one a selector picks.
#pragma once

#include <string>
#include <vector>

namespace pnf {

// One OpenCL device as the driver reports it.
struct DeviceInfo {
  int platform_index = 0;  // P of the "P:D" selector
  int device_index = 0;    // D of the "P:D" selector, counted within the platform
  std::string platform_name;
  std::string platform_vendor;  // "The pocl project", "NVIDIA Corporation", ...
  std::string device_name;
  std::string device_vendor;
  std::string type;            // "cpu", "gpu", "accelerator" or "other"
  std::string version;         // CL_DEVICE_VERSION
  std::string driver_version;  // CL_DRIVER_VERSION
  bool selected = false;       // the device `selector` picks
};

// The name of the environment variable that picks the device when no selector is given in code.
inline constexpr const char* kDeviceEnvironmentVariable = "PNF_DEVICE";

// Every device of every OpenCL platform, in platform then device order, with `selected` set on
// the one that `selector` picks. Selector syntax (SPEC, "Devices"): "cpu", "gpu", "accelerator",
// "P:D" (platform and device index), or a case-insensitive piece of the platform or device name
// or vendor (so "pocl" finds PoCL, whose platform is named "Portable Computing Language").
// An empty selector means the PNF_DEVICE variable, and if that is unset or empty: the first GPU,
// else the first CPU. No platform at all gives an empty list; a selector that matches nothing
// leaves every `selected` false (use describe_device_choice_error for the message).
// Thread safety: may be called from any thread.
std::vector<DeviceInfo> list_devices(const std::string& selector = "");

// The selector actually in force: `selector` if not empty, else the PNF_DEVICE variable, else "".
std::string effective_device_selector(const std::string& selector);

}  // namespace pnf
