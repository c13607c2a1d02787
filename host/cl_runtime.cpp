#include "cl_runtime.hpp"

#include <utility>
#include <vector>

#include "device_select.hpp"
#include "kernel_source.hpp"

namespace pnf::detail {
namespace {

std::string type_name(cl_device_type type) {
  if (type & CL_DEVICE_TYPE_GPU) return "gpu";
  if (type & CL_DEVICE_TYPE_CPU) return "cpu";
  if (type & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
  return "other";
}

struct FoundDevice {
  DeviceInfo info;
  cl::Device device;
};

// Every device of every platform. No ICD or no platform gives an empty list, not an error:
// the caller turns that into a message that says so.
std::vector<FoundDevice> enumerate_devices() {
  std::vector<FoundDevice> found;
  std::vector<cl::Platform> platforms;
  try {
    cl::Platform::get(&platforms);
  } catch (const cl::Error&) {
    return found;  // CL_PLATFORM_NOT_FOUND_KHR: no platform installed
  }
  for (std::size_t p = 0; p < platforms.size(); ++p) {
    std::vector<cl::Device> devices;
    try {
      platforms[p].getDevices(CL_DEVICE_TYPE_ALL, &devices);
    } catch (const cl::Error&) {
      continue;  // CL_DEVICE_NOT_FOUND: a platform with no usable device
    }
    for (std::size_t d = 0; d < devices.size(); ++d) {
      FoundDevice f;
      f.info.platform_index = static_cast<int>(p);
      f.info.device_index = static_cast<int>(d);
      f.info.platform_name = platforms[p].getInfo<CL_PLATFORM_NAME>();
      f.info.platform_vendor = platforms[p].getInfo<CL_PLATFORM_VENDOR>();
      f.info.device_vendor = devices[d].getInfo<CL_DEVICE_VENDOR>();
      f.info.device_name = devices[d].getInfo<CL_DEVICE_NAME>();
      f.info.type = type_name(devices[d].getInfo<CL_DEVICE_TYPE>());
      f.info.version = devices[d].getInfo<CL_DEVICE_VERSION>();
      f.info.driver_version = devices[d].getInfo<CL_DRIVER_VERSION>();
      f.device = devices[d];
      found.push_back(std::move(f));
    }
  }
  return found;
}

std::vector<DeviceInfo> infos(const std::vector<FoundDevice>& found) {
  std::vector<DeviceInfo> out;
  for (const FoundDevice& f : found) out.push_back(f.info);
  return out;
}

}  // namespace

std::string cl_error_name(cl_int code) {
  switch (code) {
#define PNF_CL_CODE(name) \
  case name: return #name;
    PNF_CL_CODE(CL_SUCCESS)
    PNF_CL_CODE(CL_DEVICE_NOT_FOUND)
    PNF_CL_CODE(CL_DEVICE_NOT_AVAILABLE)
    PNF_CL_CODE(CL_COMPILER_NOT_AVAILABLE)
    PNF_CL_CODE(CL_MEM_OBJECT_ALLOCATION_FAILURE)
    PNF_CL_CODE(CL_OUT_OF_RESOURCES)
    PNF_CL_CODE(CL_OUT_OF_HOST_MEMORY)
    PNF_CL_CODE(CL_PROFILING_INFO_NOT_AVAILABLE)
    PNF_CL_CODE(CL_BUILD_PROGRAM_FAILURE)
    PNF_CL_CODE(CL_INVALID_VALUE)
    PNF_CL_CODE(CL_INVALID_DEVICE)
    PNF_CL_CODE(CL_INVALID_CONTEXT)
    PNF_CL_CODE(CL_INVALID_COMMAND_QUEUE)
    PNF_CL_CODE(CL_INVALID_MEM_OBJECT)
    PNF_CL_CODE(CL_INVALID_BUILD_OPTIONS)
    PNF_CL_CODE(CL_INVALID_PROGRAM)
    PNF_CL_CODE(CL_INVALID_PROGRAM_EXECUTABLE)
    PNF_CL_CODE(CL_INVALID_KERNEL_NAME)
    PNF_CL_CODE(CL_INVALID_KERNEL)
    PNF_CL_CODE(CL_INVALID_ARG_INDEX)
    PNF_CL_CODE(CL_INVALID_ARG_VALUE)
    PNF_CL_CODE(CL_INVALID_ARG_SIZE)
    PNF_CL_CODE(CL_INVALID_KERNEL_ARGS)
    PNF_CL_CODE(CL_INVALID_WORK_DIMENSION)
    PNF_CL_CODE(CL_INVALID_WORK_GROUP_SIZE)
    PNF_CL_CODE(CL_INVALID_WORK_ITEM_SIZE)
    PNF_CL_CODE(CL_INVALID_GLOBAL_OFFSET)
    PNF_CL_CODE(CL_INVALID_EVENT)
    PNF_CL_CODE(CL_INVALID_OPERATION)
    PNF_CL_CODE(CL_INVALID_BUFFER_SIZE)
    PNF_CL_CODE(CL_INVALID_GLOBAL_WORK_SIZE)
#undef PNF_CL_CODE
    default: return "CL_UNKNOWN_ERROR(" + std::to_string(code) + ")";
  }
}

ClRuntime::ClRuntime(const std::string& selector) {
  const std::string& resolved = selector;
  std::vector<FoundDevice> found = enumerate_devices();
  int chosen = choose_device(infos(found), resolved);
  if (chosen < 0) throw Error(ErrorCode::device, no_device_message(infos(found), resolved));
  info_ = found[chosen].info;
  info_.selected = true;
  device_ = found[chosen].device;
  with_cl_errors(info_.device_name, [&] {
    context_ = cl::Context(device_);
    queue_ = cl::CommandQueue(context_, device_, CL_QUEUE_PROFILING_ENABLE);
  });
}

std::size_t ClRuntime::max_alloc_bytes() const {
  return with_cl_errors(info_.device_name,
                        [&] { return static_cast<std::size_t>(device_.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>()); });
}

std::vector<DeviceInfo> enumerate_device_infos() { return infos(enumerate_devices()); }

cl::Kernel ClRuntime::kernel(const std::string& file, const std::string& kernel_name, const std::string& options) {
  const std::string key = file + '\n' + options;
  auto it = programs_.find(key);
  if (it == programs_.end()) {
    cl::Program program = with_cl_errors(info_.device_name, [&] { return cl::Program(context_, kernel_source(file)); });
    try {
      program.build({device_}, options.c_str());
    } catch (const cl::Error& e) {
      std::string log;
      try {
        log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device_);
      } catch (const cl::Error&) {
        log = "(the driver gave no build log)";
      }
      throw Error(ErrorCode::device, "building OpenCL program '" + file + "' with options '" + options +
                                         "' failed with " + cl_error_name(e.err()) + " on device '" +
                                         info_.device_name + "'; build log:\n" + log);
    }
    it = programs_.emplace(key, std::move(program)).first;
  }
  return with_cl_errors(info_.device_name, [&] { return cl::Kernel(it->second, kernel_name.c_str()); });
}

std::string ClRuntime::description() const {
  return "'" + info_.device_name + "' on '" + info_.platform_name + "' (" + info_.version + ", driver " +
         info_.driver_version + ")";
}

}  // namespace pnf::detail
