// The crystallographic cell of a family's surface: which cell the standard numbers of the
// bicontinuous-phase literature refer to, beside the cell a run computes (the box of the nodal
// formula, edge a = 1). The D formula's box is the Fd-3m cell of one diamond labyrinth; the D
// surface (both labyrinths alike: a bilayer's midsurface, or alpha = 1/2) repeats on the Pn-3m
// cell of edge a/2, eight to a box (docs/science.md, "Cells"). P and G use their box.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace cmcsurf {

struct CrystallographicCell {
  std::string surface;
  std::string space_group;          // of the surface with both sides alike (alpha = 1/2)
  std::string space_group_phase1;   // of one labyrinth: the surface's away from alpha = 1/2
  int cells_per_computed_cell = 1;  // of the space group's cubic cell in the box
  double lattice_ratio = 1.0;       // its edge over the box's: cells^(-1/3)
};

// P: Im-3m, 1; D: Pn-3m, 8 (a/2); G: Ia-3d, 1. nullopt for other surfaces.
std::optional<CrystallographicCell> crystallographic_cell(const std::string& surface);

// A run's numbers per crystallographic cell (a_c = lattice_ratio a): area A_c / a_c^2, the
// surface's chi over the cells, H a_c, <K> a_c^2. Inputs are per box in box units (a = 1).
struct CellNumbers {
  double area = 0.0;                  // sigma_c
  double euler_characteristic = 0.0;  // chi per cell (whole when the box holds whole cells)
  double mean_curvature = 0.0;        // H a_c
  double mean_gaussian_curvature = 0.0;  // <K> a_c^2
};
CellNumbers per_crystallographic_cell(const CrystallographicCell& cell, double area,
                                      std::int64_t euler_characteristic_surface,
                                      double mean_curvature, double mean_gaussian_curvature);

// Gamma = sigma^(3/2) / (2 pi |chi|)^(1/2) for area sigma and chi of a surface in a cell of
// volume 1 (Hyde 1989): the same for any cell of the lattice. NaN for chi = 0.
double homogeneity_index(double area, std::int64_t euler_characteristic_surface);

}  // namespace cmcsurf
