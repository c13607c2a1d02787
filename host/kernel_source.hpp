// Assembles a kernel's OpenCL C source from the embedded files.
#pragma once

#include <string>

namespace pnf::detail {

// Returns the source of the embedded file `name` with every `#include "x"` of another embedded
// file replaced by that file's text, framed by #line markers so that a build log points at the
// real file and line. Throws pnf::Error if a file is missing.
std::string kernel_source(const std::string& name);

}  // namespace pnf::detail
