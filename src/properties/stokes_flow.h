// Permeability of the pore space of a periodic cell: Stokes flow (stokes_operator.h) driven by
// a unit mean pressure gradient along each axis (a body force f = e_j on the fluid faces),
// solved by MINRES (minres.h) with the block-diagonal FFT preconditioner
// (stokes_preconditioner.h). Darcy: <u_i> = -(k_ij / mu) dP/dx_j, so with mu = 1 and
// -dP/dx_j = 1 the column j of k is the mean velocity over the whole cell (solid included).
// Units: voxels (h = 1): k in voxel^2 (divide by n^2 for cell-size^2), velocity in voxels per
// unit time for mu = 1.
//
// Input: n and the n^3 solid fractions s in [0, 1], voxel (i, j, k) at i + n (j + n k), as for
// homogenize.h.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "properties/homogenize.h"  // LoadCaseStats, Matrix3, Vector3
#include "properties/stokes_operator.h"
#include "properties/stokes_preconditioner.h"  // VelocityPreconditioner

namespace cmcsurf::properties {

struct FlowOptions {
  // MINRES: the preconditioned residual relative to its initial value (minres.h); 1e-6
  // changes k by less than 1e-5 relative against 1e-10 (docs/properties.md).
  double tolerance = 1e-6;
  int max_iterations = 3000;  // per load case; beyond it the case is reported not converged
  double theta_min = 0.05;    // smallest wall distance of the cut cells (stokes_operator.h)
  // Shift of the velocity preconditioner (stokes_preconditioner.h), voxels^-2; 0: the lowest
  // Dirichlet eigenvalue of a channel of the pore space's hydraulic width w = 2 phi / S,
  // (pi / w)^2 (S the specific surface per voxel, phi the porosity), within [1e-4, 1].
  double sigma = 0.0;
  // The velocity block of the preconditioner: multigrid (iterations about constant in n) or
  // the earlier FFT Laplacian (iterations ~n^0.6), kept to compare (docs/properties.md).
  VelocityPreconditioner velocity_preconditioner = VelocityPreconditioner::multigrid;
  VelocityMultigridOptions multigrid;  // its cycle
};

struct FlowResult {
  Matrix3 permeability{};  // symmetrised; voxel^2
  double asymmetry = 0.0;  // max |k_ij - k_ji| / max |k_ij| before symmetrising
  std::array<LoadCaseStats, 3> load_cases{};
  // Mean speed over mean velocity along the driving axis (sum |u| / sum u_j at the voxel
  // centres): the hydraulic tortuosity; 0 where nothing flows.
  Vector3 hydraulic_tortuosity{};
  // Largest |div u| of any voxel over the largest face velocity, over the load cases: the
  // cell-by-cell mass balance (the solver's tolerance, not round-off, bounds it).
  double max_divergence = 0.0;
  double fluid_face_fraction = 0.0;  // fluid faces / all faces
  double sigma = 0.0;                // the preconditioner's shift used
  // Axes along which a cluster of voxels joined by fluid faces wraps around the cell (no
  // flow otherwise), and the pore volume (fraction of the cell: the voxels' 1 - s) in
  // clusters that wrap along no axis: closed pores, which carry no flow.
  std::array<bool, 3> percolates{};
  double closed_pore_fraction = 0.0;
  std::vector<std::string> warnings;  // axes without flow; load cases not converged
  bool converged = false;
  double seconds = 0.0;
  std::size_t bytes = 0;  // solver memory (vectors, operator, spectrum; the input not counted)
};

// Called once per solved load case (axis j; not for an axis without flow) with the operator
// and the solution (velocity blocks first, then pressure; stokes_operator.h).
using FlowVisitor = std::function<void(int axis, const StokesOperator& op, const double* x)>;

// Percolation of the fluid faces' graph (FlowResult::percolates, closed_pore_fraction).
struct FlowPercolation {
  std::array<bool, 3> percolates{};
  double closed_pore_fraction = 0.0;
};
FlowPercolation flow_percolation(const StokesOperator& op);

// Wall shear stress of a solved flow (x from the visitor), in the solver's units (mu = 1,
// unit pressure gradient, h = 1; scale by mu U / (k h) for a superficial velocity U):
// samples at every fluid face P of each component c with a wall link along an axis d != c,
// tau = mu du_c/dn at the wall, one-sided and second order through P and the fluid neighbour
// beyond it (mu u_P / theta where there is none), weighted by the link's wall area (the
// control volume's section normal to d). A proxy for |tau|: the components are sampled
// separately.
struct WallShearStats {
  double mean = 0.0, median = 0.0, p5 = 0.0, p95 = 0.0, max = 0.0;
  double wall_area = 0.0;       // sum of the weights, voxels^2
  std::vector<double> histogram;  // area fractions in kHistogramBins equal bins on [0, max]
  static constexpr int kHistogramBins = 20;
};
WallShearStats wall_shear_statistics(const StokesOperator& op, const double* x);

// Pore-solid interface area per cell volume, voxels^-1: sum of |grad s| (central differences)
// over the voxels / n^3, exact for a plane whose fractions are linear in the distance
// (s = 1/2 + d / h across a one-voxel band).
double specific_surface(int n, const std::vector<double>& solid_fraction);

// FlowOptions::sigma's automatic value for these fractions.
double automatic_sigma(int n, const std::vector<double>& solid_fraction);

// Throws std::invalid_argument when the cell has no solid face (k unbounded).
FlowResult compute_permeability(int n, const std::vector<double>& solid_fraction,
                                const FlowOptions& o = {}, const FlowVisitor& visit = {});

}  // namespace cmcsurf::properties
