// What the pictures and report.html draw: the zero set of a level-set function psi over one
// unit cell, as a triangle mesh with the local mean curvature H and the unit normal at each
// vertex. The mesh is extracted on a coarser lattice (every s-th cell centre, at most
// max_cells per side: the drawing needs far fewer triangles than the measures), while H and the
// normal come from the full-resolution psi, so the colours are those of the measured surface.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "grid/field.h"

namespace cmcsurf {

struct DrawSurface {
  // Unit-cell coordinates: the cell [h/2, 1 + h/2]^3 between the first cell centre and its
  // periodic image, so that translated copies tile seamlessly.
  std::vector<std::array<float, 3>> positions;
  std::vector<std::array<float, 3>> normals;  // -grad psi / |grad psi|: out of phase 1 (psi > 0)
  std::vector<float> curvature;               // H = -div(grad psi/|grad psi|)/2 at the vertex
  std::vector<std::array<std::uint32_t, 3>> triangles;
  int lattice_cells = 0;  // cells per side of the lattice the mesh was extracted on
  float origin = 0.0f;    // h/2: the low corner of the cell on every axis
};

// The lattice stride for an n^3 grid drawn with at most max_cells per side: the least divisor
// s of n with n / s <= max_cells.
int draw_stride(int n, int max_cells);

// psi: whole grid, ghost >= 2, halo current. max_cells >= 2. On a block of a decomposed grid
// every process calls it and rank 0 gets the surface of the whole grid (the same as from the
// whole psi); the others get an empty one.
DrawSurface draw_surface(const Field& psi, int max_cells);

// Area-weighted quantile of |H - centre| over the triangles (vertex mean per triangle), q in
// [0, 1]: the colour scale's reach.
double curvature_spread(const DrawSurface& s, double centre, double q);

}  // namespace cmcsurf
