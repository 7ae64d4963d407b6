// Parallel surfaces of a periodic surface and the lipid-length relation of bicontinuous cubic
// phases (docs/science.md, "Parallel surfaces").
//
// The surface S is the zero set of a level-set function psi on the periodic grid; d is the
// exact distance of each cell centre to S's periodic triangle mesh (signed_distance of
// mesh/scaffold.h), positive in phase 1 (psi > 0). The parallel surface at distance l on the
// phase-1 side is {d = l}, on the phase-2 side {d = -l}; its area is that of the periodic
// marching-tetrahedra mesh of d at that level, and the volume between S and it the integral of
// those areas from 0 to l (layer_volume below). Beside them, Steiner's
// formula for a smooth surface whose normal segments do not meet within l, with the normal
// pointing into phase 2 (H > 0 where phase 1 is convex):
//   A_2(l) = A + 2 (int H dA) l + (int K dA) l^2,
//   V_2(l) = A l + (int H dA) l^2 + (int K dA) l^3 / 3
// and A_1, V_1 the same with -l; int K dA = 2 pi chi (Gauss-Bonnet, chi of the surface).
#pragma once

#include <cstdint>
#include <vector>

#include "grid/field.h"

namespace cmcsurf {

// Signed distance (cell units, > 0 where psi > 0) of each cell centre to the periodic mesh of
// {psi = 0}, exact to that mesh where |d| < band, clamped to +-band beyond; halo exchanged.
Field surface_distance(const Field& psi, double band);

// The measured surface's integrals Steiner's formula needs: the area, int H dA and chi.
struct SurfaceIntegrals {
  double area = 0.0;
  double total_mean_curvature = 0.0;
  std::int64_t euler_characteristic = 0;
};
double steiner_area(const SurfaceIntegrals& s, double l);    // l < 0: the phase-1 side
double steiner_volume(const SurfaceIntegrals& s, double l);  // |V| between S and {d = -l}

struct ParallelSurface {
  double distance = 0.0;  // l > 0
  double area = 0.0, volume = 0.0;                 // measured
  double area_steiner = 0.0, volume_steiner = 0.0;  // the formula
};
struct ParallelSurfaces {
  std::vector<ParallelSurface> phase1, phase2;  // per distance, the side it lies on
};
// d: surface_distance with band > max(distances) + 2 h (halo current).
ParallelSurfaces parallel_surfaces(const Field& d, const SurfaceIntegrals& s,
                                   const std::vector<double>& distances);

// The lipid relation of a bilayer of lipids of length l on both sides of a surface in a cubic
// cell of edge a (Hyde): phi_L = 2 sigma x + (4 pi / 3) chi x^3 with x = l / a, sigma = A / a^2
// and chi per that cell (int H dA cancels between the two sides).
double lipid_fraction(double x, double sigma, std::int64_t chi);
// The smallest x > 0 with lipid_fraction(x) = phi_L, on the branch where it grows with x
// (x^2 < sigma / (2 pi |chi|) for chi < 0); NaN where phi_L is beyond that branch's maximum.
double lipid_length_ratio(double phi_L, double sigma, std::int64_t chi);
// The area of the level set {d = t} (t > 0: on the phase-1 side) and the volume between two of
// them, the integral of the areas over t (the coarea formula; |grad d| = 1 for a distance), by
// 4-point Gauss-Legendre quadrature: exact where the area is Steiner's quadratic in t. (The
// volume under d's piecewise-linear interpolant instead is biased by O(h^2 kappa^2): its
// gradient, an average of unit vectors over a tetrahedron, is shorter than 1; +0.25 % at 32^3.)
double level_area(const Field& d, double t);
double layer_volume(const Field& d, double a, double b);
// The measured bilayer: the volume fraction of {|d| < x} (both sides) ...
double bilayer_fraction(const Field& d, double x);
// ... and the x at which it equals phi_L, by Newton steps from x_start (the formula's), within
// (0, x_max); NaN where they leave it or do not converge.
double measured_lipid_length_ratio(const Field& d, double phi_L, double x_start, double x_max);

}  // namespace cmcsurf
