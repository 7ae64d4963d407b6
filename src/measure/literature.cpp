#include "measure/literature.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace cmcsurf {

namespace {

constexpr MinimalSurfaceArea kAreas[] = {
    {"P", 2.3451, "Schwarz P, per cubic cell (Schoen 1970)"},
    {"D", 3.8377, "Schwarz D, per Fd-3m box of 8 Pn-3m cells (Schoen 1970)"},
    {"G", 3.0915, "Schoen's gyroid, per cubic cell (Schoen 1970; 3.0919 in some tables)"},
};

}  // namespace

std::span<const MinimalSurfaceArea> minimal_surface_areas() { return kAreas; }

std::optional<double> minimal_surface_area(const std::string& surface) {
  for (const MinimalSurfaceArea& a : kAreas)
    if (surface == a.surface) return a.area;
  return std::nullopt;
}

double i_scp(double v) {
  constexpr double pi = std::numbers::pi;
  if (v <= 4.0 * pi / 81.0) return std::cbrt(36.0 * pi * v * v);  // sphere
  if (v <= 1.0 / pi) return 2.0 * std::sqrt(pi * v);                // cylinder
  return 2.0;                                                        // two planes
}

double i_scp_of_fraction(double alpha) { return i_scp(std::min(alpha, 1.0 - alpha)); }

}  // namespace cmcsurf
