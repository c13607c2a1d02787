#include "row_layout.hpp"

#include <cstdint>

#include "ply_scalar.hpp"

namespace pnf {

RowLayout::RowLayout(const std::vector<PlyProperty>& properties)
    : properties_(properties), offsets_(properties.size()) {
  for (std::size_t p = 0; p < properties.size(); ++p) {
    offsets_[p] = fixed_size_;
    const PlyProperty& property = properties[p];
    fixed_size_ += scalar_size(property.is_list ? property.count_type : property.type);
    if (property.is_list) fixed_ = false;
  }
}

std::size_t RowLayout::measure(const unsigned char* row) {
  if (fixed_) return fixed_size_;
  std::size_t size = 0;
  for (std::size_t p = 0; p < properties_.size(); ++p) {
    offsets_[p] = size;
    const PlyProperty& property = properties_[p];
    if (!property.is_list) {
      size += scalar_size(property.type);
      continue;
    }
    std::uint64_t count = 0;
    load_count(property.count_type, row + size, count);
    size += scalar_size(property.count_type) + count * scalar_size(property.type);
  }
  return size;
}

}  // namespace pnf
