// Effective elasticity and conductivity of a periodic cell of composite voxels: for each
// macroscopic load case (6 unit Voigt strains; 3 unit temperature gradients) the periodic
// fluctuation solves K u = -K u_macro (VoxelOperator), by CG (pcg.h) preconditioned with the
// FFT of the homogeneous solid (FftReferencePreconditioner); the effective tensor's column is
// the volume average of stress (flux) over the cell. Units and notation: voxel_element.h
// (C normalised by E_s, conductivity by k_s, Voigt order 11 22 33 23 13 12).
//
// Input: n and the n^3 solid fractions s in [0, 1], voxel (i, j, k) at i + n (j + n k).
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "properties/voxel_element.h"

namespace cmcsurf::properties {

struct SolverOptions {
  double tolerance = 1e-5;  // CG: relative preconditioned residual (pcg.h)
  int max_iterations = 1000;  // per load case; beyond it the case is reported not converged
  // Composite voxels with s below this count as void: they alone (contrast 1/s unbounded)
  // make the iterations grow with n. 0.02 changes the gyroids' tensors by 1e-4 relative at
  // 64^3 (docs/properties.md); the solid fraction removed is returned.
  double void_below = 0.02;
  // Preconditioner D M^-1 D with D the nodes' diagonal scaling (fft_preconditioner.h): fewer
  // iterations on small grids without void_below, but they grow with n; false: the plain
  // reference-medium inverse on the active nodes.
  bool diagonal_scaling = false;
};

struct LoadCaseStats {
  int iterations = 0;
  double relative_residual = 0.0;
  bool converged = false;
  double seconds = 0.0;
};

struct ElasticHomogenization {
  Matrix6 stiffness_voigt{};  // symmetrised (C + C^T) / 2, normalised by E_s
  double asymmetry = 0.0;     // max |C_ij - C_ji| / max |C_ij| before symmetrising
  double removed_solid_fraction = 0.0;  // by SolverOptions::void_below, of the cell's volume
  std::array<LoadCaseStats, 6> load_cases{};
  bool converged = false;  // every load case
  double seconds = 0.0;
  std::size_t bytes = 0;  // solver memory (vectors, mask, spectrum; the input not counted)
};

struct ConductivityHomogenization {
  Matrix3 conductivity{};  // symmetrised, normalised by k_s
  double asymmetry = 0.0;
  double removed_solid_fraction = 0.0;
  std::array<LoadCaseStats, 3> load_cases{};
  bool converged = false;
  double seconds = 0.0;
  std::size_t bytes = 0;
};

ElasticHomogenization homogenize_elasticity(int n, const std::vector<double>& solid_fraction,
                                            double poisson_ratio, const SolverOptions& o = {});
ConductivityHomogenization homogenize_conductivity(int n,
                                                   const std::vector<double>& solid_fraction,
                                                   const SolverOptions& o = {});

}  // namespace cmcsurf::properties
