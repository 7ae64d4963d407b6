#include "science/crystallographic_cell.h"

#include <cmath>
#include <limits>
#include <numbers>

namespace cmcsurf {

std::optional<CrystallographicCell> crystallographic_cell(const std::string& surface) {
  // The groups of docs/science.md's table of densities at alpha = 1/2 (bilayer: the surface's,
  // step: one labyrinth's), checked there on computed fields by their absences.
  if (surface == "P") return CrystallographicCell{"P", "Im-3m", "Pm-3m", 1, 1.0};
  if (surface == "D") return CrystallographicCell{"D", "Pn-3m", "Fd-3m", 8, 0.5};
  if (surface == "G") return CrystallographicCell{"G", "Ia-3d", "I4_132", 1, 1.0};
  return std::nullopt;
}

CellNumbers per_crystallographic_cell(const CrystallographicCell& cell, double area,
                                      std::int64_t euler_characteristic_surface,
                                      double mean_curvature, double mean_gaussian_curvature) {
  const double n = cell.cells_per_computed_cell, r = cell.lattice_ratio;
  return {area / n / (r * r), double(euler_characteristic_surface) / n, mean_curvature * r,
          mean_gaussian_curvature * r * r};
}

double homogeneity_index(double area, std::int64_t euler_characteristic_surface) {
  if (euler_characteristic_surface == 0) return std::numeric_limits<double>::quiet_NaN();
  return std::pow(area, 1.5) /
         std::sqrt(2.0 * std::numbers::pi * std::abs(double(euler_characteristic_surface)));
}

}  // namespace cmcsurf
