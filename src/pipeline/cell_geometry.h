// The geometry of a relaxed cell's labyrinths (docs/science.md, "Channels and parallel
// surfaces"): channel radii of both phases, the parallel surfaces at the user's distances with
// Steiner's formula beside them, and the lattice parameter a lipid length and lipid volume
// fraction imply. A stage of the measures of the final field (run_cmc), whole grids only.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "grid/field.h"
#include "model/cell_geometry.h"

namespace cmcsurf {

// The signed distance the equilibrium profile phi = (1 + tanh(d / (2 sqrt2 eps))) / 2 encodes:
// d = 2 sqrt(2) epsilon psi, psi = atanh(2 phi - 1) (cell units, > 0 in phase 1). Exact for
// that profile; |d| saturates at 2 sqrt(2) epsilon 14.2 where psi is clamped. psi: any ghost
// width; the result has psi's shape, halo exchanged.
Field profile_distance(const Field& psi, double epsilon);

// psi = atanh(2 phi - 1) of the final field (whole grid, ghost 2, halo current); area,
// total_mean_curvature and chi of its sharp surface; the distances; lipid_length_nm <= 0: no
// lipid relation.
CellGeometry measure_cell_geometry(const Field& psi, const SurfaceIntegrals& s,
                                   const std::vector<double>& distances, double lipid_length_nm,
                                   double lipid_fraction);

}  // namespace cmcsurf
