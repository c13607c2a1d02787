#include "staged_output.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "pnf/error.hpp"
#include "write_target.hpp"

namespace pnf::mpi::detail {
namespace {

namespace fs = std::filesystem;

// Attempts at a staging folder that another run's clean-up removed between its creation and
// its lock (a race of microseconds; more than one in a row means something else is wrong).
constexpr int kCreateAttempts = 3;

fs::path folder_of(const std::string& out_path) {
  const fs::path target(out_path);
  return target.has_parent_path() ? target.parent_path() : fs::path(".");
}

std::string staging_prefix(const std::string& out_path) {
  return "." + fs::path(out_path).filename().string() + ".pnf-mpi-";
}

[[noreturn]] void io_error(const std::string& path, const std::string& what, int error_number) {
  throw Error(ErrorCode::io, path + ": " + what + ": " + std::strerror(error_number));
}

}  // namespace

int remove_stale_staging(const std::string& out_path) {
  const std::string prefix = staging_prefix(out_path);
  std::error_code ec;
  int removed = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder_of(out_path), ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    const int fd = ::open(entry.path().c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
    if (fd < 0) continue;
    // The writing job's rank 0 holds the lock until it ends; the kernel drops it when that
    // process dies, however it dies. A file system without flock (an error other than
    // EWOULDBLOCK) tells us nothing: leave the entry.
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0) {
      std::error_code remove_ec;
      if (fs::remove_all(entry.path(), remove_ec) > 0 && !remove_ec) ++removed;
    }
    ::close(fd);
  }
  return removed;
}

StagedOutput::StagedOutput(const Agreement& agree, MPI_Comm comm, const std::string& out_path)
    : agree_(agree), out_(out_path) {
  agree_.run([&] {
    if (agree_.rank() != 0) return;
    // The file replaced: where a link at OUT leads, with its permission bits kept.
    const pnf::detail::WriteTarget replaced = pnf::detail::write_target(out_path);
    target_ = replaced.path;
    if (replaced.exists) mode_ = replaced.mode;
    remove_stale_staging(target_);
    const fs::path folder = folder_of(target_);
    for (int attempt = 0; attempt < kCreateAttempts && lock_ < 0; ++attempt) {
      std::string pattern = (folder / (staging_prefix(target_) + std::to_string(::getpid()) + "-XXXXXX")).string();
      if (::mkdtemp(pattern.data()) == nullptr) {
        io_error(out_path, "cannot create a staging folder in " + folder.string(), errno);
      }
      const int fd = ::open(pattern.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
      if (fd < 0) continue;
      struct stat status {};
      // Locked, and still there (not removed as stale by another run before the lock).
      if (::flock(fd, LOCK_EX | LOCK_NB) == 0 && ::fstat(fd, &status) == 0 && status.st_nlink > 0) {
        lock_ = fd;
        folder_ = pattern;
      } else {
        ::close(fd);
      }
    }
    if (lock_ < 0) throw Error(ErrorCode::io, out_path + ": cannot create and lock a staging folder beside it");
  });
  int length = int(folder_.size());
  check_mpi(MPI_Bcast(&length, 1, MPI_INT, 0, comm), "MPI_Bcast");
  folder_.resize(std::size_t(length));
  check_mpi(MPI_Bcast(folder_.data(), length, MPI_CHAR, 0, comm), "MPI_Bcast");
  file_ = (fs::path(folder_) / fs::path(out_path).filename()).string();
}

StagedOutput::~StagedOutput() {
  if (agree_.rank() != 0) return;
  std::error_code ec;
  if (!folder_.empty()) fs::remove_all(folder_, ec);
  if (lock_ >= 0) ::close(lock_);
}

void StagedOutput::commit(const ProgressCallback& progress, int pass, int passes) {
  const bool go_on = !progress || progress(PassProgress{pass, passes, 0.0, ProgressStage::pass, 1.0});
  agree_.run([&] {
    if (!go_on) throw Error(ErrorCode::cancelled, "cancelled before " + out_ + " was written; it is untouched");
  });
  agree_.run([&] {
    if (agree_.rank() != 0) return;
    if (mode_ >= 0 && ::chmod(file_.c_str(), mode_t(mode_)) != 0) {
      io_error(out_, "cannot give " + file_ + " the permissions of the file it replaces", errno);
    }
    if (std::rename(file_.c_str(), target_.c_str()) != 0) io_error(out_, "cannot rename " + file_ + " to it", errno);
  });
}

}  // namespace pnf::mpi::detail
