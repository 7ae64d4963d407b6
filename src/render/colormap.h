// The diverging colour scale of the pictures and of report.html: Moreland's cool-warm
// (matplotlib's "coolwarm"), blue below the centre, light grey at it, red above.
#pragma once

#include <array>
#include <span>

namespace cmcsurf {

struct Rgb {
  float r = 0, g = 0, b = 0;  // 0..1
};

// Control points (t, r, g, b), t in [0, 1], sampled from matplotlib's coolwarm at t = k/8;
// between them the scale is linear in RGB. The page draws with the same table.
struct ColorStop {
  double t;
  Rgb color;
};
std::span<const ColorStop> diverging_stops();

// The colour at t (clamped to [0, 1]).
Rgb diverging(double t);

// t of value v on a scale centred on `centre` spanning centre +- half_range.
inline double diverging_t(double v, double centre, double half_range) {
  return 0.5 + 0.5 * (v - centre) / half_range;
}

}  // namespace cmcsurf
