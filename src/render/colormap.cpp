#include "render/colormap.h"

#include <algorithm>
#include <cmath>

namespace cmcsurf {

namespace {

constexpr std::array<ColorStop, 9> kCoolWarm = {{
    {0.000, {0.2298f, 0.2987f, 0.7537f}},
    {0.125, {0.3837f, 0.5102f, 0.9178f}},
    {0.250, {0.5543f, 0.6901f, 0.9955f}},
    {0.375, {0.7240f, 0.8149f, 0.9757f}},
    {0.500, {0.8674f, 0.8644f, 0.8626f}},
    {0.625, {0.9595f, 0.7670f, 0.6741f}},
    {0.750, {0.9567f, 0.5980f, 0.4773f}},
    {0.875, {0.8654f, 0.3711f, 0.2958f}},
    {1.000, {0.7057f, 0.0156f, 0.1502f}},
}};

}  // namespace

std::span<const ColorStop> diverging_stops() { return kCoolWarm; }

Rgb diverging(double t) {
  if (!(t > 0.0)) return kCoolWarm.front().color;  // NaN reads as the low end
  if (t >= 1.0) return kCoolWarm.back().color;
  const double x = t * (kCoolWarm.size() - 1);
  const std::size_t i = std::min(std::size_t(x), kCoolWarm.size() - 2);
  const float f = float(x - double(i));
  const Rgb& a = kCoolWarm[i].color;
  const Rgb& b = kCoolWarm[i + 1].color;
  return {a.r + f * (b.r - a.r), a.g + f * (b.g - a.g), a.b + f * (b.b - a.b)};
}

}  // namespace cmcsurf
