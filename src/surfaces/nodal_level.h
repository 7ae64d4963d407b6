// The nodal approximation of a surface at a prescribed volume fraction: the level set
// {F = c} of its nodal formula (Eqs. 7-9, or expr:) with c chosen so that the sharp volume
// fraction of {F > c} is alpha. What scaffold tools threshold today, and what cmcsurf's CMC
// surface is compared with (docs/families.md).
#pragma once

#include <string>

#include "grid/field.h"

namespace cmcsurf {

struct NodalLevelSet {
  Field f;             // F + 1/2 at the cell centres (step 1's field), ghost 2, halo current
  double level = 0.0;  // c, in the units of f: phase 1 is {f > c}
  double volume_fraction = 0.0;  // sharp volume fraction of {f > c} (measure/sharp_volume.h)
};

// c such that the sharp volume fraction of {f > c} is alpha to within tol (secant steps from
// the level at which a fraction alpha of the cells has f > c). With a decomposition, f is this
// process's block and c the same on every process, equal to the whole grid's to round-off of
// the reduced sums (the first guess is the same sample, found by a bisection on its order).
NodalLevelSet nodal_level_set(const std::string& surface, double alpha, int n, double tol = 1e-7,
                              std::shared_ptr<const Decomposition> d = nullptr);

// The same for a double structure: f = |F| (F without the +1/2 offset), phase 1 = {|F| > c}:
// for c > 0 the two labyrinths of the surface F = 0 shrunk to networks, in a matrix around it.
NodalLevelSet double_level_set(const std::string& surface, double alpha, int n, double tol = 1e-7,
                               std::shared_ptr<const Decomposition> d = nullptr);

// The level-set function psi = f - c (zero on the nodal surface, > 0 in phase 1), ghost 2,
// halo current: what measure/sharp_surface.h measures. It and the profile below have f's block.
Field nodal_level_function(const NodalLevelSet& nodal);

// The nodal surface as a phase field with the equilibrium profile:
// phi = (1 + tanh(d / (2 sqrt2 eps))) / 2 with d = (f - c) / |grad f| the first-order signed
// distance (|grad f| by fourth-order central differences of the samples). Ghost 2.
Field nodal_tanh_profile(const NodalLevelSet& nodal, double epsilon);

}  // namespace cmcsurf
