#include "device_choice.hpp"

#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

namespace pnf::mpi::detail {

Device choose_device(MPI_Comm comm, const Device& requested) {
  MPI_Comm node;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  int local_rank = 0;
  MPI_Comm_rank(node, &local_rank);
  MPI_Comm_free(&node);
  Device device = requested.resolved();
  std::string selector = device.selector;
  std::transform(selector.begin(), selector.end(), selector.begin(), [](unsigned char c) { return std::tolower(c); });
  if (device.backend != Backend::opencl || !(selector.empty() || selector == "gpu")) return device;
  std::vector<DeviceInfo> gpus;
  for (const DeviceInfo& info : list_devices(device.selector)) {
    if (info.type == "gpu") gpus.push_back(info);
  }
  if (gpus.size() < 2) return device;
  const DeviceInfo& mine = gpus[std::size_t(local_rank) % gpus.size()];
  return Device::opencl(std::to_string(mine.platform_index) + ":" + std::to_string(mine.device_index));
}

std::unique_ptr<pnf::detail::FilterBackend> make_rank_backend(MPI_Comm comm, const FilterOptions& options,
                                                              FilterOptions& resolved) {
  resolved = options;
  resolved.device = choose_device(comm, options.device);  // its one collective comes first
  return pnf::detail::make_backend(resolved);
}

}  // namespace pnf::mpi::detail
