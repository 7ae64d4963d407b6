// Sharp-interface measures of the phi = 1/2 surface: its area, its mean curvature (surface
// average and local values) and their discretisation errors (docs/method.md, "Sharp measures").
//
// Appendix B's estimators average over the diffuse layer, so at a fixed epsilon they converge
// to the layer's values, not the surface's, as h -> 0. Here the surface is the zero set of
// psi = atanh(2 phi - 1): for the equilibrium profile phi = (1 + tanh(d / (2 sqrt2 eps))) / 2,
// psi = d / (2 sqrt2 eps) is a scaled signed distance d to the surface, smooth and nearly linear
// across the layer, so that
//   - the zero set of psi's piecewise-linear (Kuhn) interpolant approximates the surface to
//     O(h^2), and the sum of its triangle areas converges to the area at second order;
//   - kappa = div(grad psi / |grad psi|) by second-order central differences at cell centres,
//     interpolated trilinearly to each triangle's centroid, gives the local mean curvature
//     H = -kappa / 2 on the surface at second order.
// The level sets of psi and phi are the same, so nothing depends on how close the profile is to
// tanh except the size of the O(h^2) constants. Any other level-set function of a surface (the
// nodal F - c, say) is measured by the same level_set_surface.
#pragma once

#include <cstddef>
#include <vector>

#include "grid/field.h"

namespace cmcsurf {

// A local mean curvature H on the surface, the area w it stands for and the local Gaussian
// curvature K there.
struct CurvatureSample {
  double h = 0.0;
  double w = 0.0;
  double k = 0.0;
};

// psi = atanh(2 phi - 1), with 2 phi - 1 clamped to +-(1 - 1e-12) (|psi| <= 14.2). psi has the
// block of phi and any ghost width >= 2; its halo is exchanged here. phi's ghosts are not read.
void tanh_profile_inverse(const Field& phi, Field& psi);

// Local mean curvature of the level sets of psi at one cell: kappa = div(grad psi/|grad psi|)
// from second-order central differences (the 18 neighbours sharing a face or an edge), with
// H = -kappa/2 positive when the phase psi > 0 is convex. p points at the cell in psi's padded
// storage; 0 where |grad psi| vanishes.
double level_set_mean_curvature(const double* p, std::ptrdiff_t sy, std::ptrdiff_t sz,
                                double inv_h);
// Gaussian curvature of the level sets of psi at one cell from the same differences:
// K = g . adj(Hess psi) . g / |g|^4 with g = grad psi (Goldman 2005), independent of the sign of
// psi (1/r^2 on a sphere); 0 where |grad psi| vanishes.
double level_set_gaussian_curvature(const double* p, std::ptrdiff_t sy, std::ptrdiff_t sz,
                                    double inv_h);

// The zero set of psi's piecewise-linear interpolant over the dual cells (cubes between eight
// cell centres, split into Kuhn tetrahedra), as area-weighted curvature samples: one per
// triangle, H at its centroid, weight its area.
struct LevelSetSurface {
  double area = 0.0;
  double mean_curvature = 0.0;      // sum(a H) / sum(a)
  double mean_curvature_std = 0.0;  // sqrt(sum(a (H - mean)^2) / sum(a))
  double gaussian_curvature_integral = 0.0;  // sum(a K): 2 pi chi of a closed surface
  double willmore_energy = 0.0;              // sum(a H^2)
  std::size_t triangles = 0;
};
// Reads psi's interior and two ghost layers (halo current); works on a decomposed block, with
// the sums reduced over the processes (samples stay per process). samples, if given, receive
// one entry per triangle of this process, in a fixed order.
LevelSetSurface level_set_surface(const Field& psi,
                                  std::vector<CurvatureSample>* samples = nullptr);
// Plain twin: whole grid, periodic index wrap (no halo), serial.
LevelSetSurface level_set_surface_ref(const Field& psi,
                                      std::vector<CurvatureSample>* samples = nullptr);

// The sharp measures of a phase field: level_set_surface of tanh_profile_inverse(phi), and
// Richardson error estimates |X_h - X_2h| / 3 from the same estimator on psi averaged to the
// grid of N/2 (N even, N/2 >= 8; on a decomposed grid block by block when N/2 splits, else
// gathered up to N = 160; NaN otherwise).
struct SharpMeasures : LevelSetSurface {
  double area_error = 0.0;
  double mean_curvature_error = 0.0;
};
// phi: any ghost width (its ghosts are not read).
SharpMeasures sharp_measures(const Field& phi, std::vector<CurvatureSample>* samples = nullptr);
// The same from psi = tanh_profile_inverse(phi) (ghost 2, halo current).
SharpMeasures sharp_measures_psi(const Field& psi,
                                 std::vector<CurvatureSample>* samples = nullptr);

}  // namespace cmcsurf
