// The cloud `pnf filter` takes out of a point file (pnf/filter_file_options.hpp,
// filter_file_cloud.hpp).
#include "filter_file_cloud.hpp"

#include <cstdio>

#include "cloud_checks.hpp"
#include "pnf/error.hpp"
#include "pnf/filter_file_options.hpp"

namespace pnf {

bool reads_radii(const FilterFileOptions& options) {
  return options.automatic || (options.params.units == Units::radius && !(options.params.mean_radius > 0));
}

PointCloud cloud_to_filter(const PointFile& file, const std::string& path, const FilterFileOptions& options) {
  PointCloud cloud = file.cloud();
  if (!reads_radii(options)) {
    cloud.radii.clear();
  } else {
    detail::check_file_radii(cloud.radii, path, [&](std::size_t i) { return file.row_of_point(i); });
  }
  return cloud;
}

void detail::check_file_radii(const std::vector<double>& radii, const std::string& path,
                              const std::function<std::size_t(std::size_t)>& row_of) {
  for (std::size_t i = 0; i < radii.size(); ++i) {
    if (valid_radius(radii[i])) continue;
    char value[32];
    std::snprintf(value, sizeof value, "%g", radii[i]);
    throw Error(ErrorCode::invalid_input, path + ": vertex " + std::to_string(row_of(i)) + " has radius " + value +
                                              "; must be finite and > 0 (the mean radius comes from the radius "
                                              "property unless it is given: --radius, or absolute units)");
  }
}

}  // namespace pnf
