// pnf::write_png — saves an Image (from render_points) as a PNG file.
#pragma once

#include <string>

#include "pnf/render.hpp"

namespace pnf {

// Writes `image` to `path` as an 8-bit RGB PNG, or an 8-bit grey one when every pixel has equal
// red, green and blue (the same picture in a third of the data). Best zlib compression, no
// timestamp: the same image gives the same bytes. The data goes to a temporary file in the target's folder
// that is renamed over `path`: `path` is either replaced whole or left alone, and on failure no
// temporary file remains. The extension is not checked.
//
// Throws pnf::Error: invalid_argument when width or height is below 1 or rgb does not hold
// 3 * width * height bytes; io (naming the path and the reason) when encoding or writing fails.
// Thread safety: may run concurrently on different paths.
void write_png(const std::string& path, const Image& image);

}  // namespace pnf
