// The one internal header that includes the Khronos OpenCL C++ bindings.
#pragma once

#define CL_HPP_ENABLE_EXCEPTIONS
#define CL_HPP_TARGET_OPENCL_VERSION 120
#define CL_HPP_MINIMUM_OPENCL_VERSION 120
#include <CL/opencl.hpp>

#include <map>
#include <string>
#include <vector>

#include "pnf/device.hpp"

namespace pnf::detail {

// Every device of every platform as DeviceInfo (selected all false); empty when no ICD or
// platform is installed.
std::vector<DeviceInfo> enumerate_device_infos();

// "CL_OUT_OF_RESOURCES" for -5, ...; "CL_UNKNOWN_ERROR(<code>)" for codes it does not know.
std::string cl_error_name(cl_int code);

// Owns one device's context, profiling queue and built programs. Move-only; destructors never
// throw. Not thread safe: one runtime per thread.
class ClRuntime {
 public:
  ClRuntime(const ClRuntime&) = delete;
  ClRuntime& operator=(const ClRuntime&) = delete;
  ClRuntime(ClRuntime&&) = default;
  ClRuntime& operator=(ClRuntime&&) = default;

  // Picks the device with `selector` (docs/method.md, "Devices"; empty: PNF_DEVICE, then the default rule).
  // Throws pnf::Error(device) listing every device found when nothing matches.
  explicit ClRuntime(const std::string& selector);

  const DeviceInfo& info() const { return info_; }
  const cl::Device& device() const { return device_; }
  cl::Context& context() { return context_; }
  cl::CommandQueue& queue() { return queue_; }
  // Largest single buffer the device accepts, in bytes. Throws pnf::Error(device).
  std::size_t max_alloc_bytes() const;

  // The kernel `kernel_name` from embedded file `file`, building the program once per file and
  // option set. A failed build throws pnf::Error(device) carrying the build log and options.
  cl::Kernel kernel(const std::string& file, const std::string& kernel_name, const std::string& options = "");

  // One line: "'<device>' on '<platform>' (<version>, driver <driver>)".
  std::string description() const;

 private:
  DeviceInfo info_;
  cl::Device device_;
  cl::Context context_;
  cl::CommandQueue queue_;
  std::map<std::string, cl::Program> programs_;  // key: file + '\n' + options
};

// Runs `body`, turning a cl::Error into pnf::Error(device) that names the call, the symbolic
// code and the device: a DeviceMemoryError for the allocation codes (is_allocation_failure).
template <typename Body>
auto with_cl_errors(const std::string& device_name, Body&& body) -> decltype(body());

}  // namespace pnf::detail

#include "cl_runtime_inl.hpp"
