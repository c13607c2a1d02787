// The kernel files of kernels/, embedded into the library at build time by
// cmake/embed_files.cmake, so an installed library needs no source tree.
#pragma once

#include <string_view>
#include <vector>

namespace pnf::detail {

struct EmbeddedFile {
  const char* name;          // file name without folder, e.g. "filter.cl"
  std::string_view content;  // the file's exact bytes
};

const std::vector<EmbeddedFile>& embedded_kernel_files();

}  // namespace pnf::detail
