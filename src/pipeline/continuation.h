// Coarse-to-fine continuation (the fast mode's --coarse-levels): moving a relaxed field to the
// next finer grid, and the rule that says when the relaxation on a grid has settled
// (docs/performance.md, "The finest grid").
#pragma once

#include <span>

#include "grid/field.h"

namespace cmcsurf {

// Cell-centred trilinear interpolation from n to 2n (weights 3/4, 1/4 per axis; keeps the mean).
void prolongate_trilinear(const Field& coarse, Field& fine);

// The same interpolation applied to the interface's profile instead of phi: where every coarse
// value of a fine cell's stencil lies in the layer (|2 phi - 1| <= kProfileBand), it interpolates
// psi = atanh(2 phi - 1), which is a scaled signed distance for the tanh profile (linear across
// the layer), and returns phi = (1 + tanh psi) / 2; elsewhere (bulk, where phi is flat) it
// interpolates phi. A correction proportional to phi (1 - phi), which moves the interface and
// leaves both bulk phases alone, then restores the coarse mean (the mass the run conserves;
// interpolating psi shifts a curved interface by O(kappa h^2)).
// Interpolating phi averages the steep tanh across two coarse cells and widens the layer: the
// finer grid then spends its first steps steepening it again, at the convex splitting's fixed
// rate of about 1/2 per step whatever dt (measured in docs/performance.md). Needs the coarse
// halo current; fine's halo is exchanged here.
void prolongate_profile(const Field& coarse, Field& fine);
inline constexpr double kProfileBand = 0.999;

// A series of a relaxation's values, one per time step, has settled within tol when its last
// two changes shrank (|d_n| < |d_{n-1}| < |d_{n-2}|) and the geometric tail they predict,
// |d_n| r / (1 - r) with r the larger of the two ratios, is at most tol; or when its last
// change is zero. A drift that does not shrink (a slow pinch-off, a neck that narrows at a
// steady rate) never settles, however small each step's change. Needs four values.
bool series_settled(std::span<const double> values, double tol);

}  // namespace cmcsurf
