// Internal to the renderer: the viridis colour scale and the colour bar with its labels.
#pragma once

#include <array>

#include "pnf/render.hpp"

namespace pnf::render_detail {

using Rgb = std::array<unsigned char, 3>;

// Viridis (van der Walt and Smith, matplotlib): perceptually uniform, readable in grey and by
// the colour blind. `t` is clamped to [0, 1]; 0 is dark purple, 1 yellow.
Rgb viridis(double t);

// Draws, in the columns x >= x0 of `image`, a vertical bar from 0 (bottom) to `max_degrees`
// (top) with ticks at round steps labelled in degrees, on the background already there. Draws
// only what fits: a very small image gets the bar without labels.
void draw_colour_bar(Image& image, int x0, double max_degrees);

}  // namespace pnf::render_detail
