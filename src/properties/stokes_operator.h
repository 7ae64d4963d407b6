// Incompressible Stokes flow in the periodic cell on a staggered (MAC) grid of the voxels:
// pressure p at voxel centres, velocity component u_c on the faces normal to c (u_c of face
// (i, j, k) between voxels (i, j, k) - e_c and (i, j, k)); index i + n (j + n k) for all four
// fields. Lengths in voxels (h = 1), viscosity mu. The saddle-point system is symmetric:
//
//   [ A   B^T ] [u]   [V f]    A = mu (-Laplacian) with the no-slip wall cut in (below),
//   [ B   0   ] [p] = [ 0 ]    B = -divergence of the fluxes a u, B^T p = a (p(i) - p(i - e_c))
//
// Cut cells (finite volumes): a face's pore fraction is the mean pore fraction 1 - s of its
// two voxels, psi = that - 1/2 its level-set value (a signed distance in voxels for a wall
// across the link, exact in the cut voxels of a plane). Faces with psi <= 0 are solid: u = 0
// there, rows and columns dropped. A link from a fluid face P to a solid neighbour Q carries
// the wall's shear flux mu u_P / theta (on P's diagonal), theta in (0, 1] the distance from P
// to the wall along the link (from psi of the cut one of P, Q), clamped below at theta_min.
// P's control volume reaches 1/2 towards a fluid neighbour and theta / 2 towards the wall on
// each side: its length along axis d is l_d = l_d^- + l_d^+, its open area a = prod over the
// two other axes, its volume V = a l_c. In 1D this is Shortley-Weller's scheme, exact for the
// parabola of a slit, made symmetric by the volume weights; the wall sits at the phi = 1/2
// surface to second order, not on voxel faces. A voxel with no fluid face is inactive.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "properties/voxel_operator.h"  // Vec

namespace cmcsurf::properties {

// A voxel index along a periodic axis of n voxels, at most one step outside [0, n), wrapped.
inline int wrap(int i, int n) { return i < 0 ? i + n : i >= n ? i - n : i; }

// Wall distance from a fluid face (psi_p > 0) to the wall before a solid neighbour
// (psi_q <= 0), in link lengths, unclamped: from the cut face's own distance when only one of
// them is cut (|psi| < 1/2), else by linear interpolation.
double wall_distance(double psi_p, double psi_q);

class StokesOperator {
 public:
  // solid_fraction: n^3 values in [0, 1], kept by reference (for apply_ref; it must outlive
  // the operator).
  StokesOperator(int n, const std::vector<double>& solid_fraction, double viscosity = 1.0,
                 double theta_min = 0.05);

  int n() const { return n_; }
  std::size_t cells() const { return std::size_t(n_) * n_ * n_; }
  std::size_t size() const { return 4 * cells(); }  // u_x, u_y, u_z, p blocks of cells()
  double viscosity() const { return mu_; }
  const std::vector<double>& solid_fraction() const { return *s_; }

  // Face q of component c (at c * cells() + q): 1 fluid, 0 solid.
  bool fluid_face(int c, std::size_t q) const { return diag_[c * cells() + q] > 0.0f; }
  // 1 for a voxel with a fluid face.
  const std::vector<std::uint8_t>& active_cells() const { return active_; }
  std::size_t fluid_faces() const { return fluid_faces_; }
  // The diagonal of A / mu on each face (0 on solid faces): 6 for an interior fluid face.
  const std::vector<float>& velocity_diagonal() const { return diag_; }
  // Per face (c * cells() + q): bit d set when the neighbour in link direction d (-x, +x, -y,
  // +y, -z, +z) is fluid; the off-diagonal of A / mu is -1 there.
  const std::vector<std::uint8_t>& face_links() const { return links_; }
  // Distance (link lengths) from fluid face q of component c to the wall in direction d
  // (axis d / 2, sign - for even d); 0 when the neighbour is fluid.
  double wall_theta(int c, std::size_t q, int d) const;
  // Open area a and control volume V of fluid face q of component c (0 on solid faces).
  double face_area(int c, std::size_t q) const { return area_[c * cells() + q]; }
  double face_volume(int c, std::size_t q) const;

  // y = K x (x, y of size(), not aliased). OpenMP over z layers.
  void apply(const double* x, double* y) const;
  // y += K x in the same pass, returning x . K x (on the fluid faces and active voxels): what
  // MINRES needs without a vector for K x.
  double apply_add(const double* x, double* y) const;
  // Plain twin: recomputes every face and link from the fractions, one thread.
  void apply_ref(const double* x, double* y) const;

  // Net outflow sum a u over each voxel's faces (its mass balance; h = 1): out of cells().
  void divergence(const double* u, double* div) const;

  std::size_t bytes() const;

 private:
  int n_;
  double mu_, theta_min_;
  const std::vector<double>* s_;
  std::vector<float> diag_;            // 3 cells(): A / mu diagonal, 0 on solid faces
  std::vector<float> area_;            // 3 cells(): open area a, 0 on solid faces
  std::vector<std::uint8_t> links_;    // 3 cells(): bit d set when neighbour d is fluid
  std::vector<std::uint8_t> active_;   // cells()
  std::size_t fluid_faces_ = 0;
};

}  // namespace cmcsurf::properties
