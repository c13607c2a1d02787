// RowLayout — where each property of a PLY row lies in the binary_little_endian layout. Rows
// of an element without list properties all share one layout; with lists, each row is
// measured from its counts.
#pragma once

#include <cstddef>
#include <vector>

#include "pnf/point_file.hpp"
#include "pnf/point_file_header.hpp"

namespace pnf {

class RowLayout {
 public:
  // `properties` must outlive the layout.
  explicit RowLayout(const std::vector<PlyProperty>& properties);

  // True when no property is a list, so every row has row_size() bytes.
  bool fixed() const { return fixed_; }
  // The size of every row (fixed layouts), or the least size of a row (lists all empty).
  std::size_t row_size() const { return fixed_size_; }

  // Measures the row starting at `row` and returns its size in bytes; afterwards offset(p) is
  // where property p (for a list: its count) starts within it. Precondition: the row is
  // complete and its list counts are non-negative (as the readers guarantee).
  std::size_t measure(const unsigned char* row);
  std::size_t offset(std::size_t property) const { return offsets_[property]; }

 private:
  const std::vector<PlyProperty>& properties_;
  std::vector<std::size_t> offsets_;
  bool fixed_ = true;
  std::size_t fixed_size_ = 0;
};

}  // namespace pnf
