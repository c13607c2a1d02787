#include "device_select.hpp"

#include <algorithm>
#include <cctype>

namespace pnf::detail {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

int first_of_type(const std::vector<DeviceInfo>& devices, const std::string& type) {
  for (std::size_t i = 0; i < devices.size(); ++i) {
    if (devices[i].type == type) return static_cast<int>(i);
  }
  return -1;
}

// "P:D" with two non-negative decimal numbers; false for anything else.
bool parse_index_pair(const std::string& s, int& platform, int& device) {
  auto colon = s.find(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == s.size()) return false;
  auto all_digits = [](const std::string& t) {
    return !t.empty() && t.size() < 6 &&
           std::all_of(t.begin(), t.end(), [](unsigned char c) { return std::isdigit(c); });
  };
  std::string p = s.substr(0, colon), d = s.substr(colon + 1);
  if (!all_digits(p) || !all_digits(d)) return false;
  platform = std::stoi(p);
  device = std::stoi(d);
  return true;
}

}  // namespace

int choose_device(const std::vector<DeviceInfo>& devices, const std::string& selector) {
  std::string s = lower(selector);
  if (s.empty()) {
    int gpu = first_of_type(devices, "gpu");
    return gpu >= 0 ? gpu : first_of_type(devices, "cpu");
  }
  if (s == "cpu" || s == "gpu" || s == "accelerator") return first_of_type(devices, s);
  int platform = 0, device = 0;
  if (parse_index_pair(s, platform, device)) {
    for (std::size_t i = 0; i < devices.size(); ++i) {
      if (devices[i].platform_index == platform && devices[i].device_index == device) return static_cast<int>(i);
    }
    return -1;
  }
  for (std::size_t i = 0; i < devices.size(); ++i) {
    const DeviceInfo& d = devices[i];
    for (const std::string& name : {d.device_name, d.platform_name, d.platform_vendor, d.device_vendor}) {
      if (lower(name).find(s) != std::string::npos) return static_cast<int>(i);
    }
  }
  return -1;
}

std::string no_device_message(const std::vector<DeviceInfo>& devices, const std::string& selector) {
  std::string what = selector.empty() ? std::string("no GPU or CPU OpenCL device found")
                                      : "no OpenCL device matches '" + selector + "'";
  if (devices.empty()) {
    return what +
           "; no OpenCL platform is installed (on Debian: apt-get install pocl-opencl-icd), "
           "or use the CPU reference backend";
  }
  std::string msg = what + "; found:";
  for (const DeviceInfo& d : devices) {
    msg += " [" + std::to_string(d.platform_index) + ":" + std::to_string(d.device_index) + "] " + d.type + " '" +
           d.device_name + "' on '" + d.platform_name + "';";
  }
  msg.pop_back();
  return msg + ". Selectors: cpu, gpu, accelerator, P:D, or part of a name";
}

}  // namespace pnf::detail
