// AtomicFile — writes a file through a temporary file in the same folder that is renamed over
// the target on commit(), so that readers see either the old file or the whole new one. If
// commit() is not reached (an exception, an early return), the temporary file is removed. The
// target is the file a symbolic link at the path leads to, and a replaced file keeps its
// permission bits (write_target.hpp).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace pnf {

class AtomicFile {
 public:
  // Creates the temporary file next to the target. Throws io naming `path`, the folder and the
  // OS reason when that fails, or when the target is not a regular file.
  explicit AtomicFile(const std::string& path);
  // Removes the temporary file unless commit() succeeded. Never throws.
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  // Appends bytes (buffered). Throws io naming the path and the OS reason (e.g. a full disk).
  void write(const void* data, std::size_t size);
  void write(std::string_view text) { write(text.data(), text.size()); }

  // Flushes, syncs and closes the temporary file, then renames it to the target. Throws io on
  // failure, after removing the temporary file.
  void commit();

 private:
  void flush();
  [[noreturn]] void fail(const std::string& what, int error_number);

  std::string path_;         // as given, for the messages
  std::string target_path_;  // what the rename replaces: path_, or where its links lead (write_target.hpp)
  std::string temporary_path_;
  int descriptor_ = -1;
  bool committed_ = false;
  std::vector<char> buffer_;
  std::size_t buffered_ = 0;
};

}  // namespace pnf
