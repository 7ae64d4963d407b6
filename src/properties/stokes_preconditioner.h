// Block-diagonal preconditioner of the Stokes system (stokes_operator.h) for MINRES:
//   velocity, multigrid (the default of compute_permeability): one symmetric V-cycle on each
//             component's own cut-cell stencil A_c + mu sigma (stokes_multigrid.h);
//   velocity, fft (the earlier one, kept to compare): z_c = D (mu (L + sigma))^-1 D r_c, L the
//             periodic 7-point
//             Laplacian of the full cell, inverted by FFT (symbol sum_d (2 - 2 cos t_d)),
//             D = 0 on solid faces and sqrt(6 / A_qq) on fluid ones (the cut walls' larger
//             diagonal), so the iteration stays on the fluid faces;
//   pressure: z_p = r_p / (mu sum_faces a^2 / A_qq) on active voxels, 0 elsewhere: the
//             inverse diagonal of B diag(A)^-1 B^T, which is 1 / mu in the open fluid (there
//             the Schur complement B A^-1 B^T is spectrally equivalent to the pressure mass
//             matrix / mu; h = 1) and follows the cut walls' small areas.
// sigma > 0 keeps the mean flow (the zero wavevector, which the walls hold back) invertible;
// it is of the order of the smallest eigenvalue of A / mu (pi^2 / width^2 for a channel).
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "properties/stokes_multigrid.h"
#include "properties/stokes_operator.h"

namespace cmcsurf::properties {

struct StokesFftPlans;

enum class VelocityPreconditioner { multigrid, fft };

class StokesPreconditioner {
 public:
  // op is kept by reference.
  StokesPreconditioner(const StokesOperator& op, double sigma,
                       VelocityPreconditioner velocity = VelocityPreconditioner::fft,
                       const VelocityMultigridOptions& multigrid = {});
  ~StokesPreconditioner();
  StokesPreconditioner(const StokesPreconditioner&) = delete;
  StokesPreconditioner& operator=(const StokesPreconditioner&) = delete;

  // z = M^-1 r (size op.size(), not aliased).
  void apply(const double* r, double* z) const;
  // Plain twin of the fft kind: direct separable DFT (O(n^4)), no FFTW; small n.
  void apply_ref(const double* r, double* z) const;

  std::size_t bytes() const;

 private:
  double symbol(int kx, int ky, int kz) const;  // 1 / (mu (L + sigma)) at the wavevector
  double scale(std::size_t face) const;         // D of a face (3 cells() of them)

  const StokesOperator& op_;
  double sigma_;
  std::vector<float> pressure_weight_;  // per voxel
  std::vector<double> cos_;
  std::unique_ptr<StokesFftPlans> plans_;       // fft kind
  std::unique_ptr<VelocityMultigrid> multigrid_;  // multigrid kind
};

}  // namespace cmcsurf::properties
