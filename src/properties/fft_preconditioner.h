// Preconditioner: the inverse of the same trilinear-voxel stiffness operator for a homogeneous
// reference medium (every voxel solid), applied by FFT (FFTW). That operator is a periodic
// 27-point stencil, so each wavevector theta = 2 pi (k_x, k_y, k_z) / n decouples; with the 1D
// linear-element symbols S = 2 - 2 cos t (stiffness), M = (2 + cos t) / 3 (mass) and
// sin t (first derivative), the scalar symbol of int grad u . grad v is
//   P_dd = S_d M_e M_f,   P_de = sin t_d sin t_e M_f   (d != e; {d, e, f} = {x, y, z}),
// conductivity: K(theta) = tr P; elasticity: K(theta) = (lambda0 + mu0) P + mu0 tr P I (3x3).
// The zero wavevector (the mean, which a periodic fluctuation does not have) maps to 0.
// With a node scaling d the preconditioner is D M^-1 D: symmetric, 0 where d_n = 0 (inactive
// nodes), so the iteration stays on the reduced system. d = 1 on the active nodes is the
// plain restricted inverse (the default); VoxelOperator::node_scaling, d_n = (sum of s over
// node n's voxels / 8)^-1/2, the square root of the homogeneous diagonal over the composite
// one, needs fewer iterations on small grids when nearly void voxels are kept
// (docs/properties.md compares both).
#pragma once

#include <complex>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

namespace cmcsurf::properties {

// FFTW's planner is not thread safe: every plan of the properties solvers is made under this
// lock, after init_fftw_threads() (threads are set up once per process).
std::mutex& planner_mutex();
void init_fftw_threads();

struct FftPlans;  // FFTW plans and the spectral buffer

class FftReferencePreconditioner {
 public:
  // dofs = 1 (conductivity, k0 = 1) or 3 (elasticity with Lame constants lambda0, mu0).
  // scaling: d per node, kept by reference (null: identity).
  FftReferencePreconditioner(int n, int dofs, double lambda0, double mu0,
                             const std::vector<float>* scaling);
  ~FftReferencePreconditioner();
  FftReferencePreconditioner(const FftReferencePreconditioner&) = delete;
  FftReferencePreconditioner& operator=(const FftReferencePreconditioner&) = delete;

  // z = M^-1 r (r unchanged; r and z of n^3 dofs doubles, 64-byte aligned, not aliased).
  void apply(const double* r, double* z) const;
  // Plain twin: the same symbol through a separable direct DFT (O(n^4)), no FFTW; small n.
  void apply_ref(const double* r, double* z) const;

  // Bytes held (the spectral buffer).
  std::size_t bytes() const;

 private:
  // Solve K(theta) w = v in place for the dofs complex values at one wavevector.
  void solve_symbol(int kx, int ky, int kz, std::complex<double>* v) const;

  int n_, dofs_;
  double lambda0_, mu0_;
  const std::vector<float>* scaling_;
  std::vector<double> cos_, sin_;
  std::unique_ptr<FftPlans> plans_;
};

}  // namespace cmcsurf::properties
