#include <cstdio>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "pnf/device.hpp"

namespace pnf::cli {

Command add_devices_command(CLI::App& parent) {
  auto flags = std::make_shared<DeviceFlags>();
  CLI::App* app = parent.add_subcommand("devices", "List the OpenCL platforms and devices; * marks the one pnf uses");
  flags->add_to(*app, /*with_backend=*/false);
  return {
      app, [flags] {
        Stage stage = Stage::running;
        return guarded(stage, [&] {
          std::string selector = effective_device_selector(flags->device);
          std::vector<DeviceInfo> devices = list_devices(flags->device);
          if (devices.empty()) {
            std::fprintf(stderr, "pnf: error: no OpenCL platform found (on Debian: apt-get install pocl-opencl-icd)\n");
            return int(kDevice);
          }
          bool any = false;
          for (const DeviceInfo& d : devices) {
            any = any || d.selected;
            std::printf("%c %d:%d  %-11s %s | %s | %s | driver %s\n", d.selected ? '*' : ' ', d.platform_index,
                        d.device_index, d.type.c_str(), d.device_name.c_str(), d.platform_name.c_str(),
                        d.version.c_str(), d.driver_version.c_str());
          }
          std::printf("selector: %s\n", selector.empty() ? "(default: first GPU, else first CPU)" : selector.c_str());
          if (!any) {
            std::fprintf(stderr, "pnf: error: no device matches '%s'\n", selector.c_str());
            return int(kDevice);
          }
          return int(kOk);
        });
      }};
}

}  // namespace pnf::cli
