// The geometry of a relaxed cell's labyrinths (docs/science.md, "Channels and parallel
// surfaces"): channel radii of both phases, the parallel surfaces at the user's distances with
// Steiner's formula beside them, and the lattice parameter a lipid length and lipid volume
// fraction imply. A stage of the measures of the final field (run_cmc), whole grids only.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "grid/field.h"
#include "mesh/channel_radius.h"
#include "mesh/parallel_surfaces.h"

namespace cmcsurf {

// "0.02,0.05,0.1" -> {0.02, 0.05, 0.1}; "" -> {}. Each 0 < l < kMaxParallelDistance, at most
// kMaxParallelDistances of them; throws std::invalid_argument naming the bad entry otherwise.
constexpr double kMaxParallelDistance = 0.25;
constexpr int kMaxParallelDistances = 16;
std::vector<double> parse_parallel_distances(const std::string& text);

// The bilayer of lipids of length l (nm) at lipid volume fraction phi_L around the surface.
struct LipidLattice {
  double length_nm = 0.0, fraction = 0.0;
  // l / a and a (nm, the computed cell's edge) from lipid_length_ratio (the formula with the
  // measured area and chi) and from the measured bilayer {|d| < l}; NaN where none exists.
  double ratio_formula = 0.0, lattice_nm_formula = 0.0;
  double ratio_measured = 0.0, lattice_nm_measured = 0.0;
};

struct CellGeometry {
  ChannelRadius channels;
  SurfaceIntegrals integrals;  // Steiner's inputs
  ParallelSurfaces parallel;
  std::optional<LipidLattice> lipid;
  double seconds = 0.0;
};

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
