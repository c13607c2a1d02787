// Internal to `pnf filter IN OUT` (one process: pnf::cloud_to_filter, pnf/filter_file_options.hpp;
// across ranks: pnf::mpi::filter_file): a file's radius property checked in the file's terms.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace pnf::detail {

// Throws Error(invalid_input) naming `path` and the row (`row_of(i)`, the file's row of point i)
// of the first radius that is not finite and > 0 (valid_radius), and how to do without it.
void check_file_radii(const std::vector<double>& radii, const std::string& path,
                      const std::function<std::size_t(std::size_t)>& row_of);

}  // namespace pnf::detail
