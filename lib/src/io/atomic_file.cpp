#include "atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "pnf/error.hpp"
#include "write_target.hpp"

namespace pnf {
namespace {

constexpr std::size_t kBufferSize = std::size_t{1} << 20;
// Attempts at a fresh temporary name before giving up; a clash needs another writer using
// the same process id and counter, so more than one retry is already unusual.
constexpr int kNameAttempts = 100;

std::atomic<unsigned> temporary_counter{0};

}  // namespace

AtomicFile::AtomicFile(const std::string& path) : path_(path) {
  const detail::WriteTarget replaced = detail::write_target(path);
  target_path_ = replaced.path;
  const std::filesystem::path target(target_path_);
  std::filesystem::path folder = target.parent_path();
  if (folder.empty()) folder = ".";
  int error_number = 0;
  for (int attempt = 0; attempt < kNameAttempts; ++attempt) {
    // Hidden, and named after the target, so that a file left by a crash is recognisable.
    const std::string name = "." + target.filename().string() + ".pnf-tmp-" + std::to_string(::getpid()) + "-" +
                             std::to_string(temporary_counter.fetch_add(1));
    temporary_path_ = (folder / name).string();
    // 0666 so that a new file gets the usual permissions after the umask; a replaced file's
    // own are set below.
    descriptor_ = ::open(temporary_path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (descriptor_ >= 0) break;
    error_number = errno;
    if (error_number != EEXIST) break;
  }
  if (descriptor_ < 0) {
    throw Error(ErrorCode::io, "cannot write '" + path + "': cannot create a file in '" + folder.string() +
                                   "': " + std::strerror(error_number));
  }
  if (replaced.exists && ::fchmod(descriptor_, replaced.mode) != 0) {
    fail("cannot give the new file the permissions of the one it replaces", errno);
  }
  buffer_.resize(kBufferSize);
}

AtomicFile::~AtomicFile() {
  if (committed_) return;
  if (descriptor_ >= 0) ::close(descriptor_);
  ::unlink(temporary_path_.c_str());
}

void AtomicFile::fail(const std::string& what, int error_number) {
  if (descriptor_ >= 0) ::close(descriptor_);
  descriptor_ = -1;
  ::unlink(temporary_path_.c_str());
  throw Error(ErrorCode::io, "cannot write '" + path_ + "': " + what + ": " + std::strerror(error_number));
}

void AtomicFile::flush() {
  std::size_t done = 0;
  while (done < buffered_) {
    const ssize_t put = ::write(descriptor_, buffer_.data() + done, buffered_ - done);
    if (put < 0 && errno == EINTR) continue;
    if (put < 0) fail("write failed", errno);
    done += static_cast<std::size_t>(put);
  }
  buffered_ = 0;
}

void AtomicFile::write(const void* data, std::size_t size) {
  const auto* bytes = static_cast<const char*>(data);
  while (size > 0) {
    if (buffered_ == buffer_.size()) flush();
    const std::size_t take = std::min(size, buffer_.size() - buffered_);
    std::memcpy(buffer_.data() + buffered_, bytes, take);
    buffered_ += take;
    bytes += take;
    size -= take;
  }
}

void AtomicFile::commit() {
  flush();
  // Without the sync a crash soon after the rename could leave an empty file at the target.
  if (::fsync(descriptor_) != 0) fail("sync failed", errno);
  const int descriptor = descriptor_;
  descriptor_ = -1;
  if (::close(descriptor) != 0) fail("close failed", errno);
  if (std::rename(temporary_path_.c_str(), target_path_.c_str()) != 0) {
    fail("cannot rename '" + temporary_path_ + "' to it", errno);
  }
  committed_ = true;
}

}  // namespace pnf
