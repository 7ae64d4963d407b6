// The solids whose stiffness, conductivity and flow are computed, on the grid: the solids of
// `mesh` and `scaffold` (mesh/scaffold.h) — a network (phase 1 {phi > 1/2}, or phase 2) or a
// sheet (the wall |d| < T/2 around the phi = 1/2 surface, d the signed distance) — of the CMC
// field, or of the nodal approximation at the same porosity as peer tools build it.
//
// A voxel is a dual cell (the cube between eight neighbouring cell centres, stored at its
// lower corner's cell): its solid fraction is the exact fraction of the cube where the
// piecewise-linear interpolant of the solid's level-set function is positive
// (measure/sharp_volume.h), so a two-voxel wall is not staircased and the mean of the fractions
// is the solid's sharp volume fraction (for a network, 1 - porosity to the run's own measure).
#pragma once

#include <cmath>
#include <string>

#include "grid/field.h"
#include "mesh/scaffold.h"

namespace cmcsurf {

struct SolidSpec {
  SolidKind kind = SolidKind::kNetwork;  // kNetwork or kSheet
  bool other_phase = false;              // network: phase 2 {phi < 1/2} is the solid
  double thickness = 0.0;                // sheet: wall thickness, unit cells (> 0), or
  double porosity = NAN;                 // sheet: the thickness that leaves this porosity
};

struct VoxelSolid {
  Field fraction;               // solid fraction of each voxel, in [0, 1]; ghost 1, halo valid
  double solid_fraction = 0.0;  // mean of `fraction`: the relative density
  double porosity = 0.0;        // 1 - solid_fraction
  double thickness = 0.0;       // sheet: the wall thickness (unit cells); 0 for a network
  double level = NAN;           // nodal solids: the threshold c of the formula F
};

// The solid of a CMC field (whole grid, ghost >= 2). Throws std::invalid_argument for a sheet
// without a thickness or porosity in range, naming the accepted range.
VoxelSolid cmc_voxel_solid(const Field& phi, const SolidSpec& spec);

// How a nodal sheet is built: kBand, the level band |F| < c (what nTop, MSLattice and microgen
// print); kOffset, the wall of constant thickness around {F = 0} (a constant-thickness offset).
enum class NodalSheet { kBand, kOffset };

// The nodal solid of `surface` (Eqs. 7-9 or expr:) on an n^3 grid at `porosity`: a network
// F > c (phase 2: F < c), or a sheet (kBand or kOffset) whose c or thickness is solved for the
// porosity.
VoxelSolid nodal_voxel_solid(const std::string& surface, int n, const SolidSpec& spec,
                             double porosity, NodalSheet sheet = NodalSheet::kBand);

}  // namespace cmcsurf
