// What the CLI tests that compare the tool with the library share: the backend both run on, and
// the normals of a written file.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "pnf/normal_filter.hpp"
#include "pnf/point_file.hpp"
#include "test_backends.hpp"

namespace pnf::test {

// The OpenCL filter when a device is found, else the reference, and the --backend that picks
// the same in the tool. Both then run the same code on the same device (the tool inherits
// PNF_DEVICE), so their normals agree exactly.
struct SameBackend {
  NormalFilter* filter = nullptr;
  std::string flag;
};

inline SameBackend same_backend() {
  std::string why;
  if (NormalFilter* f = opencl_filter(why)) return {f, "opencl"};
  if (std::getenv("PNF_DEVICE")) ADD_FAILURE() << "PNF_DEVICE is set but: " << why;
  return {reference_filter(), "reference"};
}

inline std::vector<Vec3> read_normals(const std::string& file) { return read_point_file(file).cloud().normals; }

}  // namespace pnf::test
