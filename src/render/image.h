// An 8-bit RGB picture in memory (row 0 at the top), what the PNG writer encodes.
#pragma once

#include <cstdint>
#include <vector>

#include "render/colormap.h"

namespace cmcsurf {

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // width * height * 3, row-major from the top

  Image() = default;
  Image(int w, int h, Rgb background = {1, 1, 1});
  std::uint8_t* pixel(int x, int y) { return &rgb[(std::size_t(y) * width + x) * 3]; }
  const std::uint8_t* pixel(int x, int y) const { return &rgb[(std::size_t(y) * width + x) * 3]; }
  // Blends c over pixel (x, y) with opacity a in [0, 1]; outside the picture: nothing.
  void blend(int x, int y, Rgb c, float a);
  void fill_rect(int x0, int y0, int w, int h, Rgb c);
  // Copies src with its top-left corner at (x, y), clipped.
  void paste(const Image& src, int x, int y);
};

std::uint8_t to_byte(float v);

}  // namespace cmcsurf
