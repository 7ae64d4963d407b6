#include "mesh/mesh_size.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "multigrid/fas.h"

namespace cmcsurf {

double mesh_unit_mm(const std::string& unit) {
  if (unit == "um") return 1e-3;
  if (unit == "mm") return 1.0;
  if (unit == "cm") return 10.0;
  if (unit == "m") return 1e3;
  if (unit == "in") return 25.4;
  throw std::invalid_argument(fmt::format("unit '{}'; accepted: um|mm|cm|m|in", unit));
}

int grid_for_resolution(double cell_size, double resolution, int max_grid) {
  const double want = std::ceil(cell_size / resolution - 1e-9);
  if (!(want <= max_grid))
    throw std::invalid_argument(fmt::format(
        "{:g} per cell of {:g} needs a grid of {:.0f}; accepted: at most {}", resolution,
        cell_size, want, max_grid));
  for (int n = std::max(8, int(want)); n <= max_grid; ++n)
    if (check_coarsenable(n).empty()) return n;
  throw std::invalid_argument(
      fmt::format("no accepted grid between {:.0f} and {}", want, max_grid));
}

}  // namespace cmcsurf
