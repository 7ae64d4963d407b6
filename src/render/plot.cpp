#include "render/plot.h"

#include <algorithm>
#include <cmath>

namespace cmcsurf {

void draw_line(Image& img, double x0, double y0, double x1, double y1, Rgb c, double on,
               double off, double* phase, float width) {
  const double length = std::hypot(x1 - x0, y1 - y0);
  const int steps = std::max(1, int(2 * length));
  const double start = phase ? *phase : 0.0;
  for (int s = 0; s <= steps; ++s) {
    const double t = double(s) / steps;
    if (on > 0 && std::fmod(start + t * length, on + off) >= on) continue;
    const double x = x0 + (x1 - x0) * t, y = y0 + (y1 - y0) * t;
    for (int py = int(std::floor(y - 2)); py <= int(std::ceil(y + 2)); ++py)
      for (int px = int(std::floor(x - 2)); px <= int(std::ceil(x + 2)); ++px) {
        const double d = std::hypot(px + 0.5 - x, py + 0.5 - y);
        if (d < width) img.blend(px, py, c, float(0.6 * (1.0 - d / width)));
      }
  }
  if (phase) *phase += length;
}

void draw_disc(Image& img, double x, double y, double r, Rgb c, bool filled) {
  for (int py = int(std::floor(y - r - 1)); py <= int(std::ceil(y + r + 1)); ++py)
    for (int px = int(std::floor(x - r - 1)); px <= int(std::ceil(x + r + 1)); ++px) {
      const double d = std::hypot(px + 0.5 - x, py + 0.5 - y);
      const double cover = filled ? std::clamp(r + 0.5 - d, 0.0, 1.0)
                                  : std::clamp(1.0 - std::abs(d - r) / 1.2, 0.0, 1.0);
      if (cover > 0) img.blend(px, py, c, float(cover));
    }
}

}  // namespace cmcsurf
