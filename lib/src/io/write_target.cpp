#include "write_target.hpp"

#include <sys/stat.h>

#include <filesystem>

#include "pnf/error.hpp"

namespace pnf::detail {
namespace {

// Linux's own limit on the links followed in one path (MAXSYMLINKS).
constexpr int kMaxLinks = 40;

}  // namespace

WriteTarget write_target(const std::string& path) {
  namespace fs = std::filesystem;
  fs::path target(path);
  std::error_code ec;
  for (int link = 0; link < kMaxLinks && fs::is_symlink(fs::symlink_status(target, ec)); ++link) {
    const fs::path to = fs::read_symlink(target, ec);
    if (ec) break;
    target = to.is_absolute() ? to : target.parent_path() / to;
  }
  WriteTarget result;
  result.path = target.string();
  struct stat status {};
  if (::stat(result.path.c_str(), &status) == 0) {
    if (!S_ISREG(status.st_mode)) {
      throw Error(ErrorCode::io, "cannot write '" + path +
                                     "': " + (result.path == path ? "it" : "'" + result.path + "', where it leads,") +
                                     " is not a regular file");
    }
    result.exists = true;
    result.mode = status.st_mode & 07777;
  }
  return result;
}

}  // namespace pnf::detail
