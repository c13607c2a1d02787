// pnf::FilterSummary — what a filter run did (points, scale, lists, device, times, passes), for
// the caller to report; and FilterResult, the PointCloud conveniences' normals with it.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "pnf/point_cloud.hpp"

namespace pnf {

// Where the mean surfel radius came from.
enum class RadiusSource { not_used, given, property, estimate };
const char* to_string(RadiusSource source);

// What a run did, for the caller to report (the library never prints).
struct FilterSummary {
  std::size_t points = 0;
  double mean_radius = 0;  // model units; 0 with Units::absolute
  RadiusSource radius_source = RadiusSource::not_used;
  double sigma_f = 0;  // model units
  double sigma_g = 0;  // model units
  double neighbours_mean = 0;
  std::size_t neighbours_max = 0;
  std::size_t neighbour_pairs = 0;  // sum of list lengths, per pass
  std::size_t chunks = 0;           // 1 when the lists fit the memory budget
  std::size_t device_bytes = 0;     // device buffers held (0 for the reference backend)
  int allocation_retries = 0;       // times the device refused a buffer and chunks were halved
  std::string backend;
  std::string device;                   // the device, with platform and driver
  double neighbour_seconds = 0;         // counting and building the lists (all passes if chunked)
  double upload_seconds = 0;            // positions, normals and lists to the device
  std::vector<double> pass_seconds;     // wall time of each pass
  std::vector<double> kernel_seconds;   // device time of each pass (OpenCL event profiling)
  int passes_run = 0;                   // < iterations when the stop rule ended the run early
  std::size_t degenerate_kept = 0;      // normals kept because J was degenerate (docs/method.md), summed over passes
  std::vector<double> mean_change_deg;  // per pass, with the stop rule: mean angle to the previous pass
};

// The PointCloud conveniences' result.
struct FilterResult {
  std::vector<Vec3> normals;  // N unit normals, in input order
  FilterSummary summary;
};

}  // namespace pnf
