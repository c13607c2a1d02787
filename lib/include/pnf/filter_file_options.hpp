// pnf::FilterFileOptions — everything `pnf filter IN OUT` is asked to do to a file, in one value:
// built once by the CLI (or a C++ app) and used alike by the one-process run and by the
// distributed one (pnf::mpi::filter_file in pnf/mpi.hpp).
#pragma once

#include "pnf/filter_params.hpp"
#include "pnf/normal_filter.hpp"
#include "pnf/point_file.hpp"

namespace pnf {

struct FilterFileOptions {
  // The filter's settings (units, mean radius and stop rule included). Not used with `automatic`
  // but for the stop rule below.
  FilterParams params;
  // Device, memory policy, max_seconds. The limits are the whole job's: max_neighbour_pairs
  // counts the pairs of every rank together, max_seconds bounds the job's wall time.
  FilterOptions options;
  // The encoding of OUT (PLY ascii, PCD DATA); the format follows OUT's extension.
  WriteOptions write;
  // `pnf filter --auto`: sigma_f, sigma_g and the passes chosen from the data and judged
  // (improve_normals_auto, pnf/improve_normals_auto.hpp); params' settings are then not used.
  bool automatic = false;
  // >= 0: replaces params.stop_change_deg and, with `automatic`, the rule's stop rule (0 turns
  // it off). < 0 (default): not given.
  double stop_change_deg = -1;
  // Allows OUT to be IN (the file is replaced atomically). Default false: OUT = IN is refused.
  bool in_place = false;

  // The FilterParams a non-automatic run uses: params with stop_change_deg applied.
  FilterParams run_params() const {
    FilterParams p = params;
    if (stop_change_deg >= 0) p.stop_change_deg = stop_change_deg;
    return p;
  }
};

// Whether a run with `options` reads the radius property: for the mean radius, where the sigmas
// are in radius units and no mean radius is given, and with `automatic` (its estimate takes it).
bool reads_radii(const FilterFileOptions& options);

// The cloud `pnf filter` filters out of `file`, read from `path`: file.cloud(), without its radii
// where the run does not read them (so a radius property that a given mean radius or absolute
// units leave unread is no error), else with each radius checked finite and > 0: an
// Error(invalid_input) naming `path` and the file's row (not the index among the valid points).
PointCloud cloud_to_filter(const PointFile& file, const std::string& path, const FilterFileOptions& options);

}  // namespace pnf
