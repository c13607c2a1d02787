// pnf::write_png: libpng encodes into memory, then AtomicFile puts the bytes in place.
//
// libpng reports errors by longjmp. Encoding happens in one function whose only objects are
// plain pointers and ints, so a longjmp out of libpng skips no destructor; the bytes go to a
// std::vector through a callback that turns bad_alloc into png_error (a longjmp from plain C
// state, outside any try block).
#include <png.h>
#include <zlib.h>

#include <cstring>
#include <new>
#include <string>
#include <vector>

#include "io/atomic_file.hpp"
#include "pnf/error.hpp"
#include "pnf/png.hpp"

namespace pnf {
namespace {

// Where the encoder writes and what went wrong, shared with libpng's callbacks.
struct PngSink {
  std::vector<unsigned char>* bytes = nullptr;
  char message[256] = {0};
};

void on_error(png_structp png, png_const_charp message) {
  auto* sink = static_cast<PngSink*>(png_get_error_ptr(png));
  std::strncpy(sink->message, message ? message : "unknown libpng error", sizeof sink->message - 1);
  png_longjmp(png, 1);
}

void on_warning(png_structp, png_const_charp) {}  // the library never prints

void on_write(png_structp png, png_bytep data, png_size_t size) {
  auto* sink = static_cast<PngSink*>(png_get_io_ptr(png));
  bool out_of_memory = false;
  try {
    sink->bytes->insert(sink->bytes->end(), data, data + size);
  } catch (const std::bad_alloc&) {
    out_of_memory = true;
  }
  if (out_of_memory) png_error(png, "out of memory");
}

void on_flush(png_structp) {}

// Encodes the rows of a width x height image with `channels` bytes a pixel (3: RGB, 1: grey)
// into sink.bytes; returns false with sink.message on failure. `rows` holds a pointer to each
// row, prepared by the caller so that nothing here needs a destructor.
bool encode(int width, int height, int channels, png_bytep* rows, PngSink& sink) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &sink, on_error, on_warning);
  if (!png) {
    std::strncpy(sink.message, "cannot start libpng", sizeof sink.message - 1);
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    std::strncpy(sink.message, "cannot start libpng", sizeof sink.message - 1);
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, &sink, on_write, on_flush);
  png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8,
               channels == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  // Pictures are small and written once: the smallest file is worth the few milliseconds.
  png_set_compression_level(png, Z_BEST_COMPRESSION);
  png_set_rows(png, info, rows);
  png_write_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

void write_png(const std::string& path, const Image& image) {
  if (image.width < 1 || image.height < 1) {
    throw Error(ErrorCode::invalid_argument, "cannot write '" + path + "': the image is " +
                                                 std::to_string(image.width) + " x " + std::to_string(image.height) +
                                                 " pixels; both must be at least 1");
  }
  const std::size_t expected = 3 * std::size_t(image.width) * std::size_t(image.height);
  if (image.rgb.size() != expected) {
    throw Error(ErrorCode::invalid_argument,
                "cannot write '" + path + "': a " + std::to_string(image.width) + " x " + std::to_string(image.height) +
                    " RGB image needs " + std::to_string(expected) + " bytes, got " + std::to_string(image.rgb.size()));
  }
  // A picture with only grey pixels (the shaded mode) is stored as grey: the same picture in a
  // third of the data.
  bool grey = true;
  for (std::size_t i = 0; grey && i < expected; i += 3) {
    grey = image.rgb[i] == image.rgb[i + 1] && image.rgb[i] == image.rgb[i + 2];
  }
  std::vector<unsigned char> grey_levels;
  if (grey) {
    grey_levels.resize(expected / 3);
    for (std::size_t i = 0; i < grey_levels.size(); ++i) grey_levels[i] = image.rgb[3 * i];
  }
  const int channels = grey ? 1 : 3;
  std::vector<png_bytep> rows(std::size_t(image.height));
  // libpng takes non-const row pointers but only reads them when writing.
  auto* first = grey ? grey_levels.data() : const_cast<png_bytep>(image.rgb.data());
  for (int y = 0; y < image.height; ++y) {
    rows[std::size_t(y)] = first + std::size_t(channels) * std::size_t(y) * std::size_t(image.width);
  }
  std::vector<unsigned char> bytes;
  PngSink sink;
  sink.bytes = &bytes;
  if (!encode(image.width, image.height, channels, rows.data(), sink)) {
    throw Error(ErrorCode::io, "cannot write '" + path + "': PNG encoding failed: " + sink.message);
  }
  AtomicFile file(path);
  file.write(bytes.data(), bytes.size());
  file.commit();
}

}  // namespace pnf
