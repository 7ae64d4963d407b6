// Multigrid preconditioner of the velocity block of the Stokes system (stokes_operator.h):
// for each component c, z_c ~ (mu (A_c / mu + sigma))^-1 r_c on the fluid faces (0 on solid
// ones), one symmetric cycle from z = 0.
//
// Levels: the fine level is the operator's own stencil (diagonal A_qq / mu + sigma, -1 per
// fluid link). A coarse level aggregates 2 x 2 x 2 faces (ceil(n / 2) per axis, the last
// aggregate of an odd n a single layer) and is half the Galerkin product P^T A P of
// piecewise-constant prolongation P: a 7-point stencil again, whose cut walls are the sums of
// the fine ones, so the coarse grids see the pore space with its sub-voxel walls. The factor
// 1/2 corrects the aggregation's overestimate of the coarse Laplacian (a link of the coarse
// grid carries 4 fine links over twice the length). Coarsening stops at n <= 4, solved by a
// dense Cholesky factorisation. Smoother: damped Jacobi (omega = 6/7), the same sweeps before
// and after the coarse correction, so the cycle is symmetric; it is positive definite because
// each level's stencil is diagonally dominant (Jacobi converges at omega < 1) and the scaled
// coarse operators are positive definite. sigma > 0 keeps a component without any wall
// invertible.
#pragma once

#include <cstddef>
#include <vector>

#include "properties/stokes_operator.h"

namespace cmcsurf::properties {

struct VelocityMultigridOptions {
  // Measured on the gyroid network at 32^3 and 64^3 (docs/properties.md): the V-cycle with two
  // sweeps takes the least time; W-cycles take no fewer MINRES iterations.
  int sweeps = 2;   // Jacobi sweeps before and after each coarse correction
  int cycles = 1;   // visits of each coarser level: 1 V-cycle, 2 W-cycle
  double omega = 6.0 / 7.0;
};

class VelocityMultigrid {
 public:
  // op is kept by reference.
  VelocityMultigrid(const StokesOperator& op, double sigma, VelocityMultigridOptions o = {});

  // z = M^-1 r on the three velocity blocks (3 op.cells() each; r, z not aliased).
  void apply(const double* r, double* z) const;

  int levels() const { return int(levels_.size()); }
  int level_n(int level) const { return levels_[level].n; }
  // y = A_level x for component c (level 0: A_c / mu + sigma on fluid faces, 0 elsewhere);
  // x, y of level_n^3 values.
  void apply_level(int level, int c, const double* x, double* y) const;
  // Plain twin of a coarse level (level >= 1): 1/2 P^T A_{level-1} P x, prolonging x, applying
  // the finer level and summing over the aggregates with full index arithmetic.
  void apply_level_ref(int level, int c, const double* x, double* y) const;

  std::size_t bytes() const;

 private:
  struct Level {
    int n = 0;
    // Coarse levels: per component (c * cells + q) the diagonal and the weights of the links
    // to the + neighbour along x, y, z (the - links are the neighbours' + links).
    std::vector<float> diag, wx, wy, wz;
    // Scratch (mutable: apply is logically const): right-hand side, solution, residual, and
    // the W-cycle's second residual and correction.
    mutable std::vector<double> b, x, r, t, e;
  };
  struct Coarsest {
    std::vector<std::size_t> index;  // active cells of the component
    std::vector<double> cholesky;    // lower factor, row-major, index.size()^2
  };

  // One stencil pass of a level (stokes_multigrid.cpp's Pass).
  template <int kPass>
  void pass(int level, int c, const double* b, const double* x, double* out) const;
  double diagonal(int level, int c, std::size_t q) const;
  void cycle(int level, int c, const double* b, double* x) const;
  void coarsen(int level);
  void factor_coarsest();

  const StokesOperator& op_;
  double sigma_;
  VelocityMultigridOptions o_;
  std::vector<Level> levels_;
  std::vector<Coarsest> coarsest_;  // per component
};

}  // namespace cmcsurf::properties
