// Picks an OpenCL device from a selector string (docs/method.md, "Devices").
#pragma once

#include <string>
#include <vector>

#include "pnf/device.hpp"

namespace pnf::detail {

// Index into `devices` of the device `selector` picks (selector already resolved against
// PNF_DEVICE; empty means the default rule), or -1 when nothing matches.
int choose_device(const std::vector<DeviceInfo>& devices, const std::string& selector);

// The error text for a selector that matched nothing, listing every device found.
std::string no_device_message(const std::vector<DeviceInfo>& devices, const std::string& selector);

}  // namespace pnf::detail
