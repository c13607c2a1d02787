#include "pnf/device.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>

#include "cl_runtime.hpp"
#include "device_select.hpp"
#include "pnf/error.hpp"

namespace pnf {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

constexpr const char* kOpenClPrefix = "opencl:";

}  // namespace

const char* to_string(Backend backend) { return backend == Backend::opencl ? "opencl" : "reference"; }

Device Device::parse(const std::string& text) {
  const std::string name = lower(text);
  if (name == "reference") return reference();
  if (name.empty() || name == "opencl") return opencl();
  if (name.rfind(kOpenClPrefix, 0) == 0) {
    std::string selector = text.substr(std::string(kOpenClPrefix).size());
    if (selector.empty()) {
      throw Error(ErrorCode::invalid_argument,
                  "device '" + text + "': no selector after 'opencl:' (cpu, gpu, accelerator, P:D or part of a name)");
    }
    return opencl(selector);
  }
  return opencl(text);
}

Device Device::resolved() const {
  if (backend != Backend::opencl || !selector.empty()) return *this;
  const char* env = std::getenv(kDeviceEnvironmentVariable);
  return env && *env ? parse(env) : *this;
}

std::string Device::to_string() const {
  if (backend == Backend::reference) return "reference";
  return selector.empty() ? "opencl" : kOpenClPrefix + selector;
}

std::string effective_device_selector(const std::string& selector) {
  if (!selector.empty()) return selector;
  const char* env = std::getenv(kDeviceEnvironmentVariable);
  return env ? std::string(env) : std::string();
}

std::vector<DeviceInfo> list_devices(const std::string& selector) {
  std::vector<DeviceInfo> devices = detail::enumerate_device_infos();
  const Device device = Device::parse(selector).resolved();
  if (device.backend != Backend::opencl) return devices;
  const int chosen = detail::choose_device(devices, device.selector);
  if (chosen >= 0) devices[std::size_t(chosen)].selected = true;
  return devices;
}

}  // namespace pnf
