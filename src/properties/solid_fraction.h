// The voxels' solid fractions s in [0, 1] that the properties solvers take (n^3 values,
// voxel (i, j, k) at i + n (j + n k)), from a phase field or from a nodal gyroid.
#pragma once

#include <vector>

#include "grid/field.h"

namespace cmcsurf::properties {

// Solid = phase 1 = {phi > level}. Voxel (i, j, k) is the dual cell whose corners are the cell
// centres (i..i+1, j..j+1, k..k+1) of phi (so FE nodes sit on phi's samples); s is the
// fraction of it where the piecewise-linear Kuhn interpolant of phi exceeds level, the same
// interpolant as measure/linear_volume_fraction, so mean(s) equals that volume fraction.
// phi: a whole grid (not a block) with a current halo.
std::vector<double> solid_fraction_from_phi(const Field& phi, double level = 0.5);

// The solvers' layout (i + n (j + n k)) of a whole-grid field of voxel fractions
// (properties/voxel_solid.h), clamped to [0, 1].
std::vector<double> voxel_values(const Field& fraction);

// Test geometry: the nodal gyroid F = sin x cos y + sin y cos z + sin z cos x (x = 2 pi X) at
// the voxel centres; the solid is {F > c} (network) or {|F| < c} (sheet), with
// s = clamp(1/2 + d / h) and d = (F - c) / |grad F| the linearised distance to the level set
// (for the sheet, the smaller of the two sides'); c found by bisection so mean(s) = 1 - porosity.
enum class GyroidSolid { network, sheet };
std::vector<double> nodal_gyroid_solid_fraction(int n, GyroidSolid kind, double porosity);

// n^3 -> (n/2)^3 by averaging 2x2x2 blocks (n even): the coarse grid of a grid check.
std::vector<double> restrict_solid_fraction(int n, const std::vector<double>& s);

}  // namespace cmcsurf::properties
