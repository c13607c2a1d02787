// numpy arrays <-> pnf views, through the buffer protocol.
//
// An input array of float32 or float64 in native byte order, aligned, with no zero stride, is
// read in place: the view points at the array's own memory and carries its strides (C order,
// Fortran order, slices, negative steps). Anything else that numpy can turn into real numbers
// (lists, integer arrays, float16, byte-swapped or unaligned arrays, broadcast views) is first
// copied into a new C-ordered float64 array. Complex, object, string and date arrays, and
// arrays of the wrong shape, raise ValueError.
//
// All of it runs with the GIL held; the views may then be read with the GIL released for as long
// as the holder objects live (the buffer export keeps numpy from resizing the array meanwhile).
#pragma once

#include <pybind11/pybind11.h>

#include <cstddef>
#include <string>

#include "pnf/cloud_view.hpp"

namespace pnf::python {

namespace py = pybind11;

// A held buffer export (PyBuffer_Release on destruction, which needs the GIL).
class HeldBuffer {
 public:
  HeldBuffer() = default;
  HeldBuffer(const HeldBuffer&) = delete;
  HeldBuffer& operator=(const HeldBuffer&) = delete;
  ~HeldBuffer() { release(); }
  // Asks `object` for a strided buffer with its format (and writable when `writable`); throws
  // py::error_already_set on failure.
  void acquire(py::handle object, bool writable = false);
  void release();
  const Py_buffer& get() const { return buffer_; }

 private:
  Py_buffer buffer_{};
  bool held_ = false;
};

// N by 3 values from a Python object, read in place when it can be (see above).
class Vec3Input {
 public:
  // `name` is used in messages ("points must be an (N, 3) array ...").
  Vec3Input(py::handle object, const char* name);
  Vec3Input(const Vec3Input&) = delete;
  Vec3Input& operator=(const Vec3Input&) = delete;

  const Vec3ArrayView& view() const { return view_; }
  std::size_t size() const { return view_.count; }
  // True when the values had to be copied (converted) first.
  bool copied() const { return copied_; }
  // The array whose memory the view reads (the input itself, or the converted copy).
  const py::object& array() const { return array_; }
  // The dtype of a result made from this input: float32 for a float32 array (in any byte order
  // or layout), float64 for anything else, so that numpy users get their input's dtype back.
  ScalarType result_type() const { return result_type_; }

 private:
  py::object array_;
  HeldBuffer buffer_;
  Vec3ArrayView view_;
  bool copied_ = false;
  ScalarType result_type_ = ScalarType::float64;
};

// N values (radii), as Vec3Input but one-dimensional.
class ScalarInput {
 public:
  ScalarInput(py::handle object, const char* name);
  ScalarInput(const ScalarInput&) = delete;
  ScalarInput& operator=(const ScalarInput&) = delete;

  const ScalarArrayView& view() const { return view_; }
  std::size_t size() const { return view_.count; }
  bool copied() const { return copied_; }

 private:
  py::object array_;
  HeldBuffer buffer_;
  ScalarArrayView view_;
  bool copied_ = false;
};

// An (N, 3) float32 or float64 array given to be written (an `out=` argument): it must be
// writable, native, aligned and without zero strides, since writing into a copy would be lost;
// anything else raises ValueError.
class Vec3InOut {
 public:
  Vec3InOut(py::handle object, const char* name);
  Vec3InOut(const Vec3InOut&) = delete;
  Vec3InOut& operator=(const Vec3InOut&) = delete;

  const MutableVec3ArrayView& view() const { return view_; }
  std::size_t size() const { return view_.count; }
  const py::object& array() const { return array_; }

 private:
  py::object array_;
  HeldBuffer buffer_;
  MutableVec3ArrayView view_;
};

// A new C-ordered (n, 3) numpy array of `type` (float64 by default) and a view that writes into
// it.
struct Vec3Output {
  py::object array;
  MutableVec3ArrayView view;
};
Vec3Output new_vec3_array(std::size_t n, ScalarType type = ScalarType::float64);

// A new C-ordered uint8 array of the given shape (height, width, 3) and its data pointer.
py::object new_image_array(std::size_t height, std::size_t width, unsigned char** data);

// Throws ValueError (through pnf::Error(invalid_argument)) unless `size` equals `expected`.
void check_same_size(const char* name, std::size_t size, const char* other, std::size_t expected);

// os.fspath(path) as a str: accepts str and os.PathLike.
std::string path_string(py::handle path);

}  // namespace pnf::python
