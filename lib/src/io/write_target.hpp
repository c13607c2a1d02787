// Where a write to a path lands, for the two writers that finish a file under another name and
// rename it over the path (AtomicFile: one process; mpi::detail::StagedOutput: a distributed run).
#pragma once

#include <sys/types.h>

#include <string>

namespace pnf::detail {

struct WriteTarget {
  std::string path;     // the path given, or the file its chain of symbolic links ends at
  bool exists = false;  // a file is there already; `mode` then holds its permission bits
  mode_t mode = 0;
};

// A rename over a symbolic link replaces the link, not the file it leads to, and a file made
// anew gets 0666 less the umask. So the file replaced is the one a link at `path` leads to (as
// a shell's `>` writes through a link), and the writers give their new file the permission bits
// of the file it replaces (a private scan stays private). A link that leads nowhere yet is
// followed too: the file is made where it points; a loop of links (more than 40) is left to the
// rename, which replaces the last link reached. Throws Error(io) naming `path` when what is
// there is not a regular file (a folder, a device such as /dev/null through a link), which a
// rename would replace or fail on.
WriteTarget write_target(const std::string& path);

}  // namespace pnf::detail
