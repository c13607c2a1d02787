// pnf::Device, pnf::list_devices — where the filter runs: the OpenCL devices pnf can use, which one
// a selector picks, or the CPU reference.
#pragma once

#include <string>
#include <vector>

namespace pnf {

// Which implementation runs the filter.
enum class Backend {
  opencl,     // float32 OpenCL kernels on the selected device (default)
  reference,  // double-precision C++ on all CPU cores, no OpenCL needed; the judge of the kernels
};

// Returns "opencl" or "reference".
const char* to_string(Backend backend);

// Where the filter runs, as a small value parsed once from a string (as Open3D's Device):
//   "reference"          the CPU reference backend
//   "opencl"             an OpenCL device by the default rule (PNF_DEVICE, else first GPU, else CPU)
//   "opencl:SELECTOR"    the OpenCL device SELECTOR picks: cpu, gpu, accelerator, P:D, a name piece
//   "SELECTOR"           the same as "opencl:SELECTOR" (so PNF_DEVICE=gpu and --device pocl work)
//   ""                   the PNF_DEVICE variable parsed the same way, and "opencl" when it is unset
// Names are case-insensitive. Thread safety: a plain value.
struct Device {
  Backend backend = Backend::opencl;
  // OpenCL selector (see list_devices); empty: PNF_DEVICE, then the default rule. Empty for the
  // reference backend.
  std::string selector;

  // Throws pnf::Error(invalid_argument) for "opencl:" with an empty selector.
  static Device parse(const std::string& text);
  static Device reference() { return Device{Backend::reference, ""}; }
  static Device opencl(const std::string& selector = "") { return Device{Backend::opencl, selector}; }

  // The device with an empty opencl selector replaced by what PNF_DEVICE says (which may be
  // "reference"); other devices unchanged.
  Device resolved() const;
  // The canonical text that parse() reads back: "reference", "opencl" or "opencl:SELECTOR".
  std::string to_string() const;

  bool operator==(const Device& other) const { return backend == other.backend && selector == other.selector; }
  bool operator!=(const Device& other) const { return !(*this == other); }
};

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
// the one that `selector` picks (read as Device::parse reads it; "reference" selects none). Selector syntax
// (docs/method.md, "Devices"): "cpu", "gpu", "accelerator", "P:D" (platform and device index), or a case-insensitive
// piece of the platform or device name or vendor (so "pocl" finds PoCL, whose platform is named "Portable Computing
// Language"). An empty selector means the PNF_DEVICE variable, and if that is unset or empty: the first GPU, else the
// first CPU. No platform at all gives an empty list; a selector that matches nothing leaves every `selected` false
// (pnf::NormalFilter then throws an error listing the devices). Thread safety: may be called from any thread.
std::vector<DeviceInfo> list_devices(const std::string& selector = "");

// The selector actually in force: `selector` if not empty, else the PNF_DEVICE variable, else "".
// The text is returned as given (it may be "reference" or "opencl:gpu"; see Device::parse).
std::string effective_device_selector(const std::string& selector);

}  // namespace pnf
