// The matrix-free voxel stencil: K = sum over voxels e of s_e K_e, with K_e the trilinear
// element matrix of the solid (voxel_element.h) and s_e the voxel's solid fraction, on the
// periodic N^3 grid of nodes at the voxel corners (D dofs per node: 1 temperature or 3
// displacements). Voxel (i, j, k) has index i + n (j + n k); so has node (i, j, k), its
// corner 0; corner a of the voxel is node (i + a_x, j + a_y, k + a_z) wrapped.
//
// Composite voxels: each voxel's stiffness is s_e times the solid's (the Voigt mixing of
// solid and void inside a voxel). Void voxels (s_e = 0) add nothing; a node that touches no
// solid voxel is inactive (its row and column of K are zero; node_scaling() is 0 there, so the
// preconditioner keeps the iterates zero there: the reduced system on the active nodes).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "grid/field.h"  // AlignedAllocator

namespace cmcsurf::properties {

// Nodal vectors: D doubles per node, node-major (component c of node n at D n + c).
using Vec = std::vector<double, AlignedAllocator<double>>;

template <int D>
class VoxelOperator {
 public:
  static constexpr int kElementDofs = 8 * D;
  using ElementMatrix = std::array<std::array<double, kElementDofs>, kElementDofs>;
  using ElementVector = std::array<double, kElementDofs>;

  // solid_fraction: n^3 values in [0, 1], kept by reference (it must outlive the operator).
  // Voxels with s < void_below count as void (s = 0) everywhere below.
  VoxelOperator(int n, const std::vector<double>& solid_fraction, const ElementMatrix& ke,
                double void_below = 0.0);

  int n() const { return n_; }
  std::size_t nodes() const { return std::size_t(n_) * n_ * n_; }
  std::size_t size() const { return D * nodes(); }
  const ElementMatrix& element_matrix() const { return ke_; }
  // 1 for a node that touches a voxel with s > 0, else 0.
  const std::vector<std::uint8_t>& active_nodes() const { return active_; }
  // Per node (sum of s over its 8 voxels / 8)^-1/2, 0 on inactive nodes: the square root of
  // the homogeneous solid's diagonal over this one's (for the preconditioner).
  std::vector<float> node_scaling() const;

  // y = K x (x and y of size(), not aliased). Skips void voxels; OpenMP over z layers of
  // voxels in two colours (layers of one colour share no node).
  void apply(const double* x, double* y) const;
  // Plain twin: every voxel in order, full index arithmetic, one thread.
  void apply_ref(const double* x, double* y) const;

  // b += scale * sum_e s_e fe scattered to voxel e's nodes (a load applied in every voxel).
  void add_element_vector(const ElementVector& fe, double scale, double* b) const;

  // sum_e s_e (mean over voxel e of grad x) / n^3: component c, direction d at [c][d].
  std::array<std::array<double, 3>, D> weighted_mean_gradient(const double* x) const;
  // sum_e s_e / n^3 (after void_below), and the solid fraction void_below removed.
  double mean_solid_fraction() const;
  double removed_solid_fraction() const;

 private:
  int n_;
  const std::vector<double>* s_;
  double void_below_;
  ElementMatrix ke_;
  std::vector<std::uint8_t> active_;
};

extern template class VoxelOperator<1>;
extern template class VoxelOperator<3>;

}  // namespace cmcsurf::properties
