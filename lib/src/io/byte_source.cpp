#include "byte_source.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "pnf/error.hpp"

namespace pnf {
namespace {

// Large enough that a read per megabyte costs nothing next to parsing it.
constexpr std::size_t kBufferSize = std::size_t{1} << 20;

[[noreturn]] void throw_io(const std::string& path, const char* what, int error_number) {
  throw Error(ErrorCode::io, "cannot " + std::string(what) + " '" + path + "': " + std::strerror(error_number));
}

}  // namespace

ByteSource::ByteSource(const std::string& path) : path_(path) {
  descriptor_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (descriptor_ < 0) throw_io(path, "open", errno);
  struct stat info {};
  if (::fstat(descriptor_, &info) != 0) {
    const int error_number = errno;
    ::close(descriptor_);
    throw_io(path, "read", error_number);
  }
  if (!S_ISREG(info.st_mode)) {
    ::close(descriptor_);
    throw_io(path, "read", S_ISDIR(info.st_mode) ? EISDIR : EINVAL);
  }
  size_ = static_cast<std::uint64_t>(info.st_size);
  buffer_.resize(kBufferSize);
}

ByteSource::~ByteSource() { ::close(descriptor_); }

bool ByteSource::fill() {
  buffer_begin_ = 0;
  buffer_end_ = 0;
  for (;;) {
    const ssize_t got = ::read(descriptor_, buffer_.data(), buffer_.size());
    if (got > 0) {
      buffer_end_ = static_cast<std::size_t>(got);
      return true;
    }
    if (got == 0) return false;
    if (errno != EINTR) throw_io(path_, "read", errno);
  }
}

std::size_t ByteSource::read(void* destination, std::size_t count) {
  auto* out = static_cast<char*>(destination);
  std::size_t done = 0;
  while (done < count) {
    if (buffer_begin_ == buffer_end_) {
      // A large request bypasses the buffer: one copy instead of two.
      if (count - done >= buffer_.size()) {
        const ssize_t got = ::read(descriptor_, out + done, count - done);
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) throw_io(path_, "read", errno);
        if (got == 0) break;
        done += static_cast<std::size_t>(got);
        continue;
      }
      if (!fill()) break;
    }
    const std::size_t take = std::min(count - done, buffer_end_ - buffer_begin_);
    std::memcpy(out + done, buffer_.data() + buffer_begin_, take);
    buffer_begin_ += take;
    done += take;
  }
  position_ += done;
  return done;
}

ByteSource::LineStatus ByteSource::read_line(std::string& line, std::size_t max_length) {
  line.clear();
  bool any = false;
  for (;;) {
    if (buffer_begin_ == buffer_end_ && !fill()) break;
    any = true;
    const char* begin = buffer_.data() + buffer_begin_;
    const std::size_t available = buffer_end_ - buffer_begin_;
    const auto* newline = static_cast<const char*>(std::memchr(begin, '\n', available));
    const std::size_t take = newline ? static_cast<std::size_t>(newline - begin) : available;
    if (line.size() + take > max_length) {
      const std::size_t allowed = max_length - line.size();
      line.append(begin, allowed);
      buffer_begin_ += allowed;
      position_ += allowed;
      return LineStatus::too_long;
    }
    line.append(begin, take);
    buffer_begin_ += take;
    position_ += take;
    if (newline) {
      ++buffer_begin_;
      ++position_;
      break;
    }
  }
  if (!any) return LineStatus::end_of_file;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return LineStatus::line;
}

bool ByteSource::rest_is_filler() {
  unsigned char chunk[4096];
  for (;;) {
    const std::size_t got = read(chunk, sizeof chunk);
    if (got == 0) return true;
    for (std::size_t i = 0; i < got; ++i) {
      const unsigned char c = chunk[i];
      if (!(c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\0')) return false;
    }
  }
}

}  // namespace pnf
