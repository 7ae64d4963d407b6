// Channel radii of the two labyrinths of a periodic unit cell: at each cell of a phase, the
// radius of the largest ball inside the phase that contains it, from morphometry's local
// thickness (mesh/morphometry.h, the pore size `scaffold` reports in mm) on the cells: a ball's
// radius is the distance from its centre cell to the nearest cell centre outside the phase, in
// units of the computed cell (a = 1). Its maximum is the largest inscribed sphere of the
// labyrinth; its volume-weighted percentiles describe the channels. Voxel resolution: a ball of
// radius 0.3 reads 0.274 at 32^3, a cylinder of 0.2 reads 0.182 (the centre cell is off the
// ball's centre; about -0.7 h).
#pragma once

#include <vector>

#include "grid/field.h"
#include "mesh/morphometry.h"

namespace cmcsurf {

struct ChannelRadius {
  // Radii in cell units over the cells of each phase: phase 1 = {psi > 0}, phase 2 = the rest.
  // fraction: the phase's share of the cells.
  ThicknessStats phase1, phase2;
};

// psi: any level-set function of the surface (phi - 1/2, atanh(2 phi - 1)); whole grid, its
// interior only is read. A cell belongs to phase 1 where psi > 0.
ChannelRadius channel_radius(const Field& psi);

// The same of one phase given as a 0/1 mask of the n^3 cells (x fastest).
ThicknessStats channel_radius_of(const std::vector<std::uint8_t>& inside, int n);

}  // namespace cmcsurf
