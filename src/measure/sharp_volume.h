// Sharp volume fraction of phase 1 = {phi > 1/2} (Section 2.1's V(phi)), to well below a cell.
//
// phi is known at cell centres. Each dual cell (the cube between 8 neighbouring centres) is
// split into the 6 Kuhn tetrahedra around its main diagonal; on each, phi is interpolated
// linearly, and the fraction of the tetrahedron where the interpolant exceeds 1/2 has a closed
// form in the 4 vertex values (tet_fraction_above). The sum over all dual cells is the volume
// enclosed by the 1/2 iso-surface of the piecewise-linear interpolant (linear_volume_fraction):
// exact for fields that are linear across the interface, second order in h for smooth fields,
// with an O(kappa h^2) bias on curved interfaces (a chord lies inside the arc).
//
// sharp_volume_fraction removes that bias: it interpolates psi = phi - (Lap_h phi +
// D_h phi) / 24 instead, with Lap_h the 7-point Laplacian times h^2 and D_h the second difference
// along the split's diagonal (1, 1, 1). For a quadratic f the Kuhn interpolant exceeds f by
// h^2 (Lap f + d.Hf.d) / 24 on average over the cube, so psi's interpolant matches phi on average
// wherever the interface cuts the cells; planes stay exact. Measured on a tanh sphere
// (r = 0.3): error 1.5e-4 -> 2e-5 at 64^3, 3.9e-5 -> 2e-6 at 128^3 (docs/volume.md).
#pragma once

#include <cmath>
#include <vector>

#include "grid/field.h"

namespace cmcsurf {

// Fraction of a tetrahedron where the linear function with vertex values g[0..3] is > 0.
// One positive vertex p: prod_q t_pq with t_pq = g_p / (g_p - g_q) along its three edges; one
// non-positive vertex: 1 minus the same product from it; two and two: the wedge
// t11 t12 + t12 t21 (1 - t11) + t21 t22 (1 - t12) (three tetrahedra of the cut prism).
double tet_fraction_above(const double g[4]);

// sum + 6 + 6 + ... (count times, in that order), as the sweeps add a run of inside dual cells.
// Where sum and the total share a binade, every partial sum lies in it too and 6 is a multiple
// of its spacing (sum < 2^53), so each addition is exact and one addition of 6 count gives the
// same bits; where they do not, the additions run one by one.
inline double add_sixes(double sum, int count) {
  const double total = sum + 6.0 * count;
  if (sum > 0.0 && std::ilogb(sum) == std::ilogb(total)) return total;
  for (int c = 0; c < count; ++c) sum += 6.0;
  return sum;
}

// Volume fraction of {phi_h > level} for the piecewise-linear interpolant of phi. Reads the
// interior and one ghost layer (the caller keeps the halo current).
double linear_volume_fraction(const Field& phi, double level = 0.5);
// Plain loop twin: periodic index wrap (no halo), every tetrahedron of every dual cell.
double linear_volume_fraction_ref(const Field& phi);

// The fraction of each dual cell (the cube between the centres of cells i..i+1, j..j+1,
// k..k+1 of a whole grid, stored at (i, j, k) of `fraction`, which must have phi's shape)
// where the piecewise-linear interpolant of phi exceeds level: the volume the estimators above
// add up, cube by cube (its mean is linear_volume_fraction). Voxel solids for the properties
// (properties/voxel_solid.h). Reads one ghost layer of phi (halo current); writes the interior
// of `fraction` only.
void dual_cell_fractions(const Field& phi, double level, Field& fraction);
void dual_cell_fractions_ref(const Field& phi, double level, Field& fraction);  // index wrap

// psi = phi - (Lap_h phi + D_h phi) / 24 of the bias correction above, halo exchanged
// (psi: the block of phi, ghost >= 1). phi needs ghost >= 2 with a current halo.
void curvature_corrected(const Field& phi, Field& psi);

// The bias-corrected estimator above: the volume fraction reported as V(phi) (Section 2.1),
// linear_volume_fraction of curvature_corrected(phi). Needs ghost >= 2 with a current halo.
double sharp_volume_fraction(const Field& phi);
double sharp_volume_fraction_ref(const Field& phi);  // plain twin, periodic index wrap

// sharp_volume_fraction's sweep, plane by plane, for a pass over phi that has other work
// (step_measures). One per thread: add_plane(k, sixths) adds the tetrahedron fractions of the
// dual cells of plane k to the thread's running sum in the cells' order, keeping psi on the two
// planes of cells those span, (nx + 1) x (ny + 1) values each, the last row and column (and
// the top plane of the block) from phi's ghosts, which hold the neighbours' (or the periodic
// wrap's) values, so psi there equals the exchanged halo's. A thread's planes in increasing k
// reuse the upper plane. The threads' sums, added over the processes and divided by
// 6 x the global cells, are the fraction. phi: ghost >= 2, halo current, alive while swept.
class SharpVolumeSweep {
 public:
  explicit SharpVolumeSweep(const Field& phi);
  void add_plane(int k, double& sixths);

 private:
  void fill(std::vector<double>& q, int k) const;
  const Field& phi_;
  std::vector<double> lower_, upper_;      // psi on planes k and k + 1
  std::vector<double> col_min_, col_max_;  // a row's column extremes
  std::vector<unsigned char> kind_;        // a row's dual cells: outside, inside, cut
  int filled_ = -2;                        // the plane upper_ holds
};

}  // namespace cmcsurf
