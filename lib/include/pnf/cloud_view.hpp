// pnf::Vec3ArrayView, pnf::CloudView — the caller's arrays, read (or written) in place.
//
// The library's entry points take views so that an app (or numpy, or an MPI rank) hands over
// its own memory: N by 3 positions and normals as float or double, rows and components at any
// byte stride. Nothing is copied to build a view; a view does not own its memory, which must
// outlive every call it is passed to. Values are read as double (float widens exactly), so a
// float view and a double view of the same float values give bit-identical results.
//
// Thread safety: views are plain values; concurrent reads of one view are safe.
#pragma once

#include <cstddef>
#include <type_traits>
#include <vector>

#include "pnf/point_cloud.hpp"

namespace pnf {

// The element type of a view.
enum class ScalarType { float32, float64 };

// Returns "float32" or "float64".
const char* to_string(ScalarType type);

namespace detail {
template <typename Pointer>
struct StridedRows {
  Pointer data = nullptr;
  std::size_t count = 0;  // N rows
  ScalarType type = ScalarType::float64;
  std::ptrdiff_t row_stride = 0;        // bytes from row i to row i + 1; 0 means packed (3 elements)
  std::ptrdiff_t component_stride = 0;  // bytes from x to y to z within a row; 0 means packed

  std::size_t element_bytes() const { return type == ScalarType::float32 ? 4 : 8; }
  std::ptrdiff_t row_step() const { return row_stride != 0 ? row_stride : std::ptrdiff_t(3 * element_bytes()); }
  std::ptrdiff_t component_step() const {
    return component_stride != 0 ? component_stride : std::ptrdiff_t(element_bytes());
  }
  // Address of component c (0..2) of row i.
  auto address(std::size_t i, int c) const {
    using Byte = std::conditional_t<std::is_const_v<std::remove_pointer_t<Pointer>>, const char, char>;
    return static_cast<Byte*>(data) + std::ptrdiff_t(i) * row_step() + c * component_step();
  }
  double get(std::size_t i, int c) const {
    const auto* p = address(i, c);
    if (type == ScalarType::float32) return double(*reinterpret_cast<const float*>(p));
    return *reinterpret_cast<const double*>(p);
  }
  Vec3 at(std::size_t i) const { return {get(i, 0), get(i, 1), get(i, 2)}; }
  bool empty() const { return count == 0; }
};
}  // namespace detail

// N by 3 values (positions or normals) in the caller's memory, read only.
struct Vec3ArrayView : detail::StridedRows<const void*> {
  Vec3ArrayView() = default;
  Vec3ArrayView(const void* data, std::size_t count, ScalarType type, std::ptrdiff_t row_stride = 0,
                std::ptrdiff_t component_stride = 0)
      : StridedRows{data, count, type, row_stride, component_stride} {}
  Vec3ArrayView(const double* xyz, std::size_t count) : Vec3ArrayView(xyz, count, ScalarType::float64) {}
  Vec3ArrayView(const float* xyz, std::size_t count) : Vec3ArrayView(xyz, count, ScalarType::float32) {}
  // The whole vector (empty vector: an empty view).
  Vec3ArrayView(const std::vector<Vec3>& values)  // NOLINT: implicit on purpose, PointCloud's arrays
      : Vec3ArrayView(values.empty() ? nullptr : values[0].data(), values.size()) {}
};

// N by 3 values in the caller's memory that a call writes (the new normals).
struct MutableVec3ArrayView : detail::StridedRows<void*> {
  MutableVec3ArrayView() = default;
  MutableVec3ArrayView(void* data, std::size_t count, ScalarType type, std::ptrdiff_t row_stride = 0,
                       std::ptrdiff_t component_stride = 0)
      : StridedRows{data, count, type, row_stride, component_stride} {}
  MutableVec3ArrayView(double* xyz, std::size_t count) : MutableVec3ArrayView(xyz, count, ScalarType::float64) {}
  MutableVec3ArrayView(float* xyz, std::size_t count) : MutableVec3ArrayView(xyz, count, ScalarType::float32) {}
  MutableVec3ArrayView(std::vector<Vec3>& values)  // NOLINT: implicit on purpose
      : MutableVec3ArrayView(values.empty() ? nullptr : values[0].data(), values.size()) {}

  // Writes v into row i, rounding to float for a float32 view.
  void set(std::size_t i, const Vec3& v) const {
    for (int c = 0; c < 3; ++c) {
      auto* p = address(i, c);
      if (type == ScalarType::float32) {
        *reinterpret_cast<float*>(p) = float(v[c]);
      } else {
        *reinterpret_cast<double*>(p) = v[c];
      }
    }
  }
};

// N values (surfel radii) in the caller's memory, read only.
struct ScalarArrayView {
  const void* data = nullptr;
  std::size_t count = 0;
  ScalarType type = ScalarType::float64;
  std::ptrdiff_t stride = 0;  // bytes from value i to i + 1; 0 means packed

  ScalarArrayView() = default;
  ScalarArrayView(const void* data, std::size_t count, ScalarType type, std::ptrdiff_t stride = 0)
      : data(data), count(count), type(type), stride(stride) {}
  ScalarArrayView(const std::vector<double>& values)  // NOLINT: implicit on purpose
      : ScalarArrayView(values.empty() ? nullptr : values.data(), values.size(), ScalarType::float64) {}

  bool empty() const { return count == 0; }
  double get(std::size_t i) const {
    const std::ptrdiff_t step = stride != 0 ? stride : std::ptrdiff_t(type == ScalarType::float32 ? 4 : 8);
    const char* p = static_cast<const char*>(data) + std::ptrdiff_t(i) * step;
    return type == ScalarType::float32 ? double(*reinterpret_cast<const float*>(p))
                                       : *reinterpret_cast<const double*>(p);
  }
};

// A point cloud in the caller's memory: N positions, N normals (or none) and N radii (or none).
struct CloudView {
  Vec3ArrayView positions;
  Vec3ArrayView normals;  // empty when the points have no normals
  ScalarArrayView radii;  // empty when the points have no radius

  CloudView() = default;
  CloudView(Vec3ArrayView positions, Vec3ArrayView normals = {}, ScalarArrayView radii = {})
      : positions(positions), normals(normals), radii(radii) {}
  CloudView(const PointCloud& cloud)  // NOLINT: implicit on purpose, every PointCloud call is a view call
      : positions(cloud.positions), normals(cloud.normals), radii(cloud.radii) {}

  std::size_t size() const { return positions.count; }
  bool has_normals() const { return !normals.empty(); }
  bool has_radii() const { return !radii.empty(); }
};

}  // namespace pnf
