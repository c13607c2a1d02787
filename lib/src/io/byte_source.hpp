// ByteSource — buffered reading of a regular file, by lines or by bytes, that knows how many
// bytes are left (so that counts read from a file can be checked before anything is
// allocated from them).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace pnf {

class ByteSource {
 public:
  enum class LineStatus { line, end_of_file, too_long };

  // Opens `path`. Throws io naming the path and the OS reason when it is missing, unreadable,
  // or not a regular file.
  explicit ByteSource(const std::string& path);
  ~ByteSource();
  ByteSource(const ByteSource&) = delete;
  ByteSource& operator=(const ByteSource&) = delete;

  const std::string& path() const { return path_; }
  std::uint64_t size() const { return size_; }
  std::uint64_t position() const { return position_; }
  std::uint64_t remaining() const { return size_ - position_; }

  // Reads up to `count` bytes into `destination`; fewer only at the end of the file. Throws io
  // on a read error.
  std::size_t read(void* destination, std::size_t count);

  // Reads one line into `line` without its '\n' or a '\r' before it. Returns end_of_file when
  // no byte was left, and too_long (having consumed max_length bytes) when no '\n' came within
  // max_length bytes.
  LineStatus read_line(std::string& line, std::size_t max_length);

  // Reads what is left and says whether it is only line ends or padding (spaces, tabs, NULs),
  // which some writers add after the data; anything else means the header's counts are short.
  bool rest_is_filler();

  // The longest body line a text reader takes: a file with no newlines is rejected after this
  // many bytes instead of being read into one string.
  static constexpr std::size_t kMaxBodyLine = std::size_t{1} << 30;

 private:
  bool fill();  // refills the buffer; false at the end of the file

  std::string path_;
  int descriptor_ = -1;
  std::uint64_t size_ = 0;
  std::uint64_t position_ = 0;  // bytes handed to the caller
  std::vector<char> buffer_;
  std::size_t buffer_begin_ = 0;  // next unread byte in buffer_
  std::size_t buffer_end_ = 0;
};

}  // namespace pnf
