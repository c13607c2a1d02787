#include <cmath>
#include <sstream>
#include <string>

#include "pnf/error.hpp"
#include "pnf/render.hpp"

namespace pnf {
namespace {

// Larger images are almost surely a typo (16384^2 RGB is already 768 MiB).
constexpr int kMaxImageSide = 16384;
// Disks of 100 spacings blur any model into a blob; beyond that it is a typo, and the drawing
// cost grows with the square of the radius.
constexpr double kMaxRadiusScale = 100;
// The narrowest drawing area left beside the colour bar that is still a picture.
constexpr int kMinDrawingWidth = 16;

std::string number(double value) {
  std::ostringstream s;
  s << value;
  return s.str();
}

[[noreturn]] void bad(const std::string& field, const std::string& value, const std::string& rule) {
  throw Error(ErrorCode::invalid_argument, field + " must be " + rule + ", got " + value);
}

}  // namespace

void RenderOptions::validate() const {
  if (width < 1 || width > kMaxImageSide) bad("width", std::to_string(width), "1 to 16384 pixels");
  if (height < 1 || height > kMaxImageSide) bad("height", std::to_string(height), "1 to 16384 pixels");
  if (!std::isfinite(azimuth_degrees)) bad("azimuth", number(azimuth_degrees), "a finite number of degrees");
  if (!(elevation_degrees >= -90 && elevation_degrees <= 90)) {
    bad("elevation", number(elevation_degrees), "-90 to 90 degrees");
  }
  const bool light_finite = std::isfinite(light[0]) && std::isfinite(light[1]) && std::isfinite(light[2]);
  if (!light_finite || (light[0] == 0 && light[1] == 0 && light[2] == 0)) {
    bad("light", number(light[0]) + "," + number(light[1]) + "," + number(light[2]), "a finite, non-zero direction");
  }
  if (!(radius_scale > 0 && radius_scale <= kMaxRadiusScale)) {
    bad("radius scale", number(radius_scale), "above 0 and at most 100");
  }
  if (!(ambient >= 0 && std::isfinite(ambient))) bad("ambient", number(ambient), "finite and >= 0");
  if (!(diffuse >= 0 && std::isfinite(diffuse))) bad("diffuse", number(diffuse), "finite and >= 0");
  if (!(specular >= 0 && std::isfinite(specular))) bad("specular", number(specular), "finite and >= 0");
  if (!(shininess > 0 && std::isfinite(shininess))) bad("shininess", number(shininess), "finite and > 0");
  if (!(error_max_degrees > 0 && error_max_degrees <= 180)) {
    bad("error max", number(error_max_degrees), "above 0 and at most 180 degrees");
  }
  if (colour_bar_width < 0) bad("colour bar width", std::to_string(colour_bar_width), ">= 0");
  if (mode == RenderMode::error && width - colour_bar_width < kMinDrawingWidth) {
    bad("width", std::to_string(width),
        "at least the colour bar width plus 16 in error mode (" + std::to_string(colour_bar_width + kMinDrawingWidth) +
            ")");
  }
  if (frame) {
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(frame->min[k]) || !std::isfinite(frame->max[k]) || frame->min[k] > frame->max[k]) {
        bad("frame", "min " + number(frame->min[k]) + " max " + number(frame->max[k]) + " on axis " + "xyz"[k],
            "finite with min <= max on each axis");
      }
    }
  }
  if (threads < 0) bad("threads", std::to_string(threads), ">= 0");
}

}  // namespace pnf
