// Text on pictures: stb_truetype (Debian libstb-dev) rasterising DejaVu Sans, which is
// compiled into the binary (render/assets.h), anti-aliased and alpha-blended.
#pragma once

#include <string_view>

#include "render/image.h"

namespace cmcsurf {

enum class Align { kLeft, kCenter, kRight };

// Width in pixels of UTF-8 text at a font size of px pixels (ascent + descent).
int text_width(std::string_view utf8, float px);

// Draws UTF-8 text with its baseline at y, starting at, centred on or ending at x.
void draw_text(Image& image, int x, int y, float px, std::string_view utf8, Rgb color,
               Align align = Align::kLeft);

}  // namespace cmcsurf
