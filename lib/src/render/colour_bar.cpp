#include "colour_bar.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace pnf::render_detail {
namespace {

// Viridis sampled at 9 evenly spaced points (matplotlib's _viridis_data at 0, 1/8, ..., 1);
// linear interpolation between them stays within a few levels of the full 256-entry table.
constexpr double kViridis[9][3] = {
    {68, 1, 84},    {71, 44, 122}, {59, 81, 139},  {44, 113, 142}, {33, 144, 141},
    {39, 173, 129}, {92, 200, 99}, {170, 220, 50}, {253, 231, 37},
};

// A 5 x 7 pixel font for the labels: digits, '.', '+', and the degree sign. Each row is 5 bits,
// the leftmost pixel in the highest bit.
struct Glyph {
  char character;
  int width;  // columns used, from the left
  unsigned char rows[7];
};
constexpr Glyph kFont[] = {
    {'0', 5, {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}}, {'1', 5, {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', 5, {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}}, {'3', 5, {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', 5, {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}}, {'5', 5, {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', 5, {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}}, {'7', 5, {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', 5, {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}}, {'9', 5, {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'.', 2, {0x00, 0x00, 0x00, 0x00, 0x00, 0x18, 0x18}}, {'+', 5, {0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00}},
    {'d', 4, {0x0C, 0x12, 0x12, 0x0C, 0x00, 0x00, 0x00}},  // the degree sign
};
constexpr int kGlyphHeight = 7;
constexpr int kGlyphGap = 1;  // blank columns after each glyph, in font pixels

// Tick steps in degrees; the smallest that gives at most kMaxTicks intervals is used.
constexpr double kTickSteps[] = {0.1, 0.2, 0.5, 1, 2, 5, 10, 15, 20, 30, 45, 60, 90};
constexpr int kMaxTicks = 6;

const Glyph* find_glyph(char c) {
  for (const Glyph& g : kFont)
    if (g.character == c) return &g;
  return nullptr;
}

int text_width(const std::string& text, int scale) {
  int w = 0;
  for (char c : text)
    if (const Glyph* g = find_glyph(c)) w += (g->width + kGlyphGap) * scale;
  return w;
}

void set_pixel(Image& image, int x, int y, const Rgb& colour) {
  if (x < 0 || y < 0 || x >= image.width || y >= image.height) return;
  unsigned char* p = &image.rgb[3 * (std::size_t(y) * image.width + x)];
  p[0] = colour[0];
  p[1] = colour[1];
  p[2] = colour[2];
}

// Draws `text` with its top-left corner at (x, y), each font pixel a scale x scale square.
void draw_text(Image& image, int x, int y, const std::string& text, int scale, const Rgb& colour) {
  for (char c : text) {
    const Glyph* g = find_glyph(c);
    if (!g) continue;
    for (int row = 0; row < kGlyphHeight; ++row)
      for (int col = 0; col < g->width; ++col)
        if (g->rows[row] & (0x10 >> col))
          for (int dy = 0; dy < scale; ++dy)
            for (int dx = 0; dx < scale; ++dx) set_pixel(image, x + col * scale + dx, y + row * scale + dy, colour);
    x += (g->width + kGlyphGap) * scale;
  }
}

std::string label(double degrees) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", degrees);
  return std::string(text) + "d";
}

}  // namespace

Rgb viridis(double t) {
  t = std::clamp(std::isfinite(t) ? t : 1.0, 0.0, 1.0);
  const double x = t * 8;
  const int i = std::min(int(x), 7);
  const double f = x - i;
  Rgb c;
  for (int k = 0; k < 3; ++k) c[k] = (unsigned char)std::lround(kViridis[i][k] * (1 - f) + kViridis[i + 1][k] * f);
  return c;
}

void draw_colour_bar(Image& image, int x0, double max_degrees) {
  const Rgb ink{0, 0, 0};
  // Font pixels are doubled on images tall enough that single pixels would look tiny.
  const int scale = image.height >= 240 ? 2 : 1;
  const int glyph_height = kGlyphHeight * scale;
  // The bar leaves half a label height above and below so the end labels fit in the image.
  const int top = std::max(glyph_height, image.height / 10);
  const int bottom = image.height - 1 - top;
  const int bar_x = x0 + std::max(2, (image.width - x0) / 12);
  const int bar_width = std::max(4, (image.width - x0) / 6);
  if (bottom <= top) return;
  for (int y = top; y <= bottom; ++y) {
    const Rgb colour = viridis(double(bottom - y) / double(bottom - top));
    for (int x = bar_x; x < bar_x + bar_width; ++x) set_pixel(image, x, y, colour);
  }
  // A thin frame keeps the dark end apart from dark surroundings and the light end from white.
  for (int y = top - 1; y <= bottom + 1; ++y) {
    set_pixel(image, bar_x - 1, y, ink);
    set_pixel(image, bar_x + bar_width, y, ink);
  }
  for (int x = bar_x - 1; x <= bar_x + bar_width; ++x) {
    set_pixel(image, x, top - 1, ink);
    set_pixel(image, x, bottom + 1, ink);
  }

  double step = kTickSteps[std::size(kTickSteps) - 1];
  for (double s : kTickSteps) {
    if (max_degrees / s <= kMaxTicks + 1e-9) {
      step = s;
      break;
    }
  }
  const int label_x = bar_x + bar_width + 3 * scale;
  const int span = bottom - top;
  int last_label_y = image.height * 2;  // labels are drawn bottom up; this one is below all
  auto tick = [&](double value, const std::string& text) {
    const int y = bottom - int(std::lround(span * value / max_degrees));
    for (int x = bar_x + bar_width; x < label_x - scale; ++x) set_pixel(image, x, y, ink);
    const int text_top = y - glyph_height / 2;
    if (last_label_y - text_top < glyph_height + scale) return;  // would overlap the one below
    std::string shown = text;
    // Without the "+" when only the number fits.
    if (label_x + text_width(shown, scale) > image.width && shown.back() == '+') shown.pop_back();
    if (label_x + text_width(shown, scale) > image.width) return;
    draw_text(image, label_x, text_top, shown, scale, ink);
    last_label_y = text_top;
  };
  const int ticks = int(std::floor(max_degrees / step + 1e-9));
  for (int i = 0; i <= ticks; ++i) {
    const double value = i * step;
    // The top end gets its own label; a tick within half a step below it would crowd it.
    if (i > 0 && value > max_degrees - 0.5 * step) continue;
    tick(value, label(value));
  }
  // Angles at or above the top end share its colour, hence the "+".
  tick(max_degrees, label(max_degrees) + "+");
}

}  // namespace pnf::render_detail
