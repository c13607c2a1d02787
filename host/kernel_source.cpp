#include "kernel_source.hpp"

#include <set>
#include <sstream>

#include "embedded_kernels.hpp"
#include "pnf/error.hpp"

namespace pnf::detail {
namespace {

std::string_view find_file(const std::string& name) {
  for (const EmbeddedFile& file : embedded_kernel_files()) {
    if (name == file.name) return file.content;
  }
  throw Error(ErrorCode::device, "kernel file '" + name + "' is not embedded in this build of pnf");
}

// Inlines includes recursively; each file at most once (the headers have include guards, and
// this keeps the output small).
void append_with_includes(const std::string& name, std::set<std::string>& seen, std::string& out) {
  if (!seen.insert(name).second) return;
  std::istringstream lines{std::string(find_file(name))};
  std::string line;
  int line_number = 0;
  out += "#line 1 \"" + name + "\"\n";
  while (std::getline(lines, line)) {
    ++line_number;
    const std::string directive = "#include \"";
    if (line.rfind(directive, 0) == 0) {
      std::string included = line.substr(directive.size(), line.find('"', directive.size()) - directive.size());
      append_with_includes(included, seen, out);
      out += "#line " + std::to_string(line_number + 1) + " \"" + name + "\"\n";
      continue;
    }
    out += line;
    out += '\n';
  }
}

}  // namespace

std::string kernel_source(const std::string& name) {
  std::set<std::string> seen;
  std::string out;
  append_with_includes(name, seen, out);
  return out;
}

}  // namespace pnf::detail
