// What a run reports of its cell's geometry (pipeline/cell_geometry.h measures it; docs/science.md,
// "Channels and parallel surfaces"): the distances a user asks for, channel radii, parallel
// surfaces and the lipid relation's lattice parameter.
#pragma once

#include <optional>
#include <string>
#include <vector>

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

}  // namespace cmcsurf
