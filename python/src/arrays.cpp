#include "arrays.hpp"

#include <cstdint>
#include <cstring>

#include "pnf/error.hpp"

namespace pnf::python {
namespace {

py::module_ numpy() { return py::module_::import("numpy"); }

std::string shape_text(const py::object& array) { return py::str(array.attr("shape")).cast<std::string>(); }

// dtype kinds numpy can convert to float64 without losing meaning: bool, signed, unsigned, float.
bool real_kind(char kind) { return kind == 'b' || kind == 'i' || kind == 'u' || kind == 'f'; }

// The element type a buffer can be read as in place, or false when it needs a copy.
bool direct_type(const Py_buffer& b, ScalarType* type) {
  const char* f = b.format != nullptr ? b.format : "B";
  // '@', '=' and (on a little-endian host, which is all pnf is built for) '<' mean native order.
  if (*f == '@' || *f == '=' || *f == '<') ++f;
  if (f[0] == 'd' && f[1] == '\0' && b.itemsize == 8) {
    *type = ScalarType::float64;
    return true;
  }
  if (f[0] == 'f' && f[1] == '\0' && b.itemsize == 4) {
    *type = ScalarType::float32;
    return true;
  }
  return false;
}

bool aligned(const void* p, std::ptrdiff_t stride, std::size_t item) {
  return reinterpret_cast<std::uintptr_t>(p) % item == 0 && stride % std::ptrdiff_t(item) == 0;
}

// np.asarray(object), checked to hold real numbers and to have `ndim` dimensions (N, 3) or (N,).
// `*copied` is set when numpy had to build new memory (a list, an object with only __array__).
py::object as_real_array(py::handle object, const char* name, int ndim, const char* expected_shape, bool* copied) {
  py::object array;
  *copied = !(PyObject_CheckBuffer(object.ptr()) || py::hasattr(object, "__array_interface__") ||
              py::hasattr(object, "__array_struct__"));
  try {
    array = numpy().attr("asarray")(object);
  } catch (py::error_already_set& e) {
    throw Error(ErrorCode::invalid_argument,
                std::string(name) + " must be " + expected_shape + " array of numbers: " + e.what());
  }
  const std::string kind = array.attr("dtype").attr("kind").cast<std::string>();
  if (kind.size() != 1 || !real_kind(kind[0])) {
    throw Error(ErrorCode::invalid_argument, std::string(name) +
                                                 " must hold real numbers (float32 or float64), got dtype " +
                                                 py::str(array.attr("dtype")).cast<std::string>());
  }
  const auto shape = array.attr("shape").cast<py::tuple>();
  const bool ok = int(shape.size()) == ndim && (ndim == 1 || shape[1].cast<long long>() == 3);
  if (!ok) {
    throw Error(ErrorCode::invalid_argument,
                std::string(name) + " must be " + expected_shape + " array, got shape " + shape_text(array));
  }
  return array;
}

py::object float64_copy(const py::object& array) {
  return numpy().attr("array")(array, py::arg("dtype") = numpy().attr("float64"), py::arg("order") = "C");
}

}  // namespace

void HeldBuffer::acquire(py::handle object, bool writable) {
  release();
  const int flags = PyBUF_STRIDES | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0);
  if (PyObject_GetBuffer(object.ptr(), &buffer_, flags) != 0) throw py::error_already_set();
  held_ = true;
}

void HeldBuffer::release() {
  if (held_) PyBuffer_Release(&buffer_);
  held_ = false;
}

Vec3Input::Vec3Input(py::handle object, const char* name) {
  array_ = as_real_array(object, name, 2, "an (N, 3)", &copied_);
  if (py::str(array_.attr("dtype").attr("name")).cast<std::string>() == "float32") {
    result_type_ = ScalarType::float32;
  }
  ScalarType type = ScalarType::float64;
  buffer_.acquire(array_);
  const Py_buffer* b = &buffer_.get();
  std::size_t n = std::size_t(b->shape[0]);
  auto usable = [&] {
    if (!direct_type(*b, &type)) return false;
    const std::size_t item = std::size_t(b->itemsize);
    // A zero stride (np.broadcast_to) would read as "packed" in a view; such arrays are copied.
    if (n > 1 && b->strides[0] == 0) return false;
    if (b->strides[1] == 0) return false;
    return aligned(b->buf, b->strides[0], item) && aligned(b->buf, b->strides[1], item);
  };
  if (!usable()) {
    buffer_.release();
    array_ = float64_copy(array_);
    copied_ = true;
    buffer_.acquire(array_);
    b = &buffer_.get();
    type = ScalarType::float64;
  }
  // One row: its stride is never used, so call it packed (numpy may report anything there).
  const std::ptrdiff_t row_stride = n > 1 ? b->strides[0] : 0;
  view_ = Vec3ArrayView(n > 0 ? b->buf : nullptr, n, type, row_stride, b->strides[1]);
}

ScalarInput::ScalarInput(py::handle object, const char* name) {
  array_ = as_real_array(object, name, 1, "an (N,)", &copied_);
  ScalarType type = ScalarType::float64;
  buffer_.acquire(array_);
  const Py_buffer* b = &buffer_.get();
  const std::size_t n = std::size_t(b->shape[0]);
  const bool usable = direct_type(*b, &type) && !(n > 1 && b->strides[0] == 0) &&
                      aligned(b->buf, b->strides[0], std::size_t(b->itemsize));
  if (!usable) {
    buffer_.release();
    array_ = float64_copy(array_);
    copied_ = true;
    buffer_.acquire(array_);
    b = &buffer_.get();
    type = ScalarType::float64;
  }
  view_ = ScalarArrayView(n > 0 ? b->buf : nullptr, n, type, n > 1 ? b->strides[0] : 0);
}

Vec3InOut::Vec3InOut(py::handle object, const char* name) {
  bool copied = false;
  array_ = as_real_array(object, name, 2, "an (N, 3)", &copied);
  const std::string what =
      std::string(name) + " must be a writable, aligned float32 or float64 array of its own memory";
  if (copied)
    throw Error(ErrorCode::invalid_argument, what + " (got " + py::str(py::type::of(object)).cast<std::string>() + ")");
  try {
    buffer_.acquire(array_, true);
  } catch (py::error_already_set& e) {
    throw Error(ErrorCode::invalid_argument, what + ": " + e.what());
  }
  const Py_buffer& b = buffer_.get();
  const std::size_t n = std::size_t(b.shape[0]);
  ScalarType type = ScalarType::float64;
  const bool usable = direct_type(b, &type) && !(n > 1 && b.strides[0] == 0) && b.strides[1] != 0 &&
                      aligned(b.buf, b.strides[0], std::size_t(b.itemsize)) &&
                      aligned(b.buf, b.strides[1], std::size_t(b.itemsize));
  if (!usable) {
    throw Error(ErrorCode::invalid_argument, what + ", got dtype " + py::str(array_.attr("dtype")).cast<std::string>() +
                                                 " with strides " +
                                                 py::str(array_.attr("strides")).cast<std::string>());
  }
  view_ = MutableVec3ArrayView(n > 0 ? b.buf : nullptr, n, type, n > 1 ? b.strides[0] : 0, b.strides[1]);
}

Vec3Output new_vec3_array(std::size_t n, ScalarType type) {
  Vec3Output out;
  const bool single = type == ScalarType::float32;
  out.array = numpy().attr("empty")(py::make_tuple(n, 3), py::arg("dtype") = single ? "float32" : "float64");
  HeldBuffer b;
  b.acquire(out.array);
  // The array is ours and C-ordered; its memory lives as long as out.array.
  out.view = MutableVec3ArrayView(b.get().buf, n, type);
  return out;
}

py::object new_image_array(std::size_t height, std::size_t width, unsigned char** data) {
  py::object array = numpy().attr("empty")(py::make_tuple(height, width, 3), py::arg("dtype") = numpy().attr("uint8"));
  HeldBuffer b;
  b.acquire(array);
  *data = static_cast<unsigned char*>(b.get().buf);
  return array;
}

void check_same_size(const char* name, std::size_t size, const char* other, std::size_t expected) {
  if (size != expected) {
    throw Error(ErrorCode::invalid_argument, std::string(name) + " has " + std::to_string(size) + " rows but " + other +
                                                 " has " + std::to_string(expected));
  }
}

std::string path_string(py::handle path) {
  py::object s = py::module_::import("os").attr("fspath")(path);
  if (!py::isinstance<py::str>(s)) {
    throw Error(ErrorCode::invalid_argument, "a path must be str or os.PathLike of str, got bytes");
  }
  return s.cast<std::string>();
}

}  // namespace pnf::python
