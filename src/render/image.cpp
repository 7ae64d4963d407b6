#include "render/image.h"

#include <algorithm>
#include <cmath>

namespace cmcsurf {

std::uint8_t to_byte(float v) {
  return std::uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

Image::Image(int w, int h, Rgb background) : width(w), height(h), rgb(std::size_t(w) * h * 3) {
  fill_rect(0, 0, w, h, background);
}

void Image::blend(int x, int y, Rgb c, float a) {
  if (x < 0 || y < 0 || x >= width || y >= height || !(a > 0.0f)) return;
  a = std::min(a, 1.0f);
  std::uint8_t* p = pixel(x, y);
  const float src[3] = {c.r, c.g, c.b};
  for (int k = 0; k < 3; ++k) p[k] = to_byte((1.0f - a) * (p[k] / 255.0f) + a * src[k]);
}

void Image::fill_rect(int x0, int y0, int w, int h, Rgb c) {
  const std::uint8_t v[3] = {to_byte(c.r), to_byte(c.g), to_byte(c.b)};
  for (int y = std::max(y0, 0); y < std::min(y0 + h, height); ++y)
    for (int x = std::max(x0, 0); x < std::min(x0 + w, width); ++x)
      std::copy(v, v + 3, pixel(x, y));
}

void Image::paste(const Image& src, int x, int y) {
  for (int j = 0; j < src.height; ++j) {
    const int ty = y + j;
    if (ty < 0 || ty >= height) continue;
    for (int i = 0; i < src.width; ++i) {
      const int tx = x + i;
      if (tx < 0 || tx >= width) continue;
      std::copy(src.pixel(i, j), src.pixel(i, j) + 3, pixel(tx, ty));
    }
  }
}

}  // namespace cmcsurf
