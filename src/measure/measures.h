// Geometric and thermodynamic measures of a phase field (paper Section 2, 3 and Appendix B).
// Every function reads the interior and the ghost layers of phi; the caller keeps the halo
// current (phi.exchange_halo()). Functions that need two ghost layers say so.
#pragma once

#include "grid/field.h"

namespace cmcsurf {

// W(phi) = 0.25 phi^2 (1 - phi)^2, the double well of Section 2.2.
inline double double_well(double phi) {
  const double a = phi * (1.0 - phi);
  return 0.25 * a * a;
}
// W'(phi) = phi^3 - 1.5 phi^2 + 0.5 phi.
inline double double_well_prime(double phi) { return phi * (phi * (phi - 1.5) + 0.5); }

// Mean of phi over the cells (the conserved "mass", equal to the mean volume fraction).
double mass(const Field& phi);

// Fraction of cells with phi > 1/2 (Section 2.1's V(phi) on the grid).
double volume_fraction(const Field& phi);

// Discrete l2 norm of Section 3: sqrt(sum phi^2 / N^3), and of a difference.
double l2_norm(const Field& a);
double l2_diff(const Field& a, const Field& b);

// Discrete free energy F(phi) = 6 sqrt2 sum [W(phi)/eps + eps/2 |grad_h phi|^2] h^3 (Section 2.2)
// with |grad_h phi|^2 the sum of squared face differences / h^2, the gradient that matches the
// 7-point Laplacian, so that the convex-splitting scheme provably does not increase it.
double energy(const Field& phi, double epsilon);
double energy_ref(const Field& phi, double epsilon);  // plain loop twin

// Area A(phi) = sum 6 sqrt2 eps |grad_d phi|^2 h^3 with the fourth-order central gradient of
// Appendix B: the diffuse layer's area (report key area_diffuse; the surface's own area is
// measure/sharp_surface.h). Needs ghost >= 2.
double area(const Field& phi, double epsilon);
double area_ref(const Field& phi, double epsilon);

// Surface-averaged mean curvature of Appendix B (report key mean_curvature_diffuse; the
// surface's own is measure/sharp_surface.h): vertex-centred normals m = grad phi from the
// eight cells around each vertex, kappa = div_d(m/|m|) at cell centres, and
// H = -1/2 sum(kappa w) / sum(w) with w = |grad_d phi|^2 (fourth-order gradient).
// Sign: H = 1/r > 0 for a sphere of phase 1 (phi > 1/2 inside) of radius r, as in Section 2.5.
// Needs ghost >= 2.
// Vertices where |m| < 1e-12 / (4h) (no phi variation around them) get n = 0.
double mean_curvature(const Field& phi);
double mean_curvature_ref(const Field& phi);  // plain loop twin of mean_curvature

// Mean curvature from the chemical potential (Section 2.5). Our nu = W'(phi) - eps^2 Lap_d phi
// equals eps/(6 sqrt2) mu. At an equilibrium mu is constant and the solvability (Gibbs-Thomson)
// condition of the sharp-interface limit gives mu [phi] = sigma 2H with jump [phi] = 1 and
// surface tension sigma = 1 (F is normalised so that F -> area), i.e. H = mu/2 = 3 sqrt2 nu/eps.
// The paper's H ~ mu/3 comes from evaluating its pointwise relation only at phi = 1/2 and is
// 2/3 of the geometric value at equilibrium (see docs/method.md). Returned as the
// |grad_d phi|^2-weighted average over the grid. Away from equilibrium the factor depends on
// the profile: for the tanh profile of a surface it returns (6/5) H. Needs ghost >= 2.
double mean_curvature_mu(const Field& phi, double epsilon);
double mean_curvature_mu_ref(const Field& phi, double epsilon);  // plain loop twin

// How far phi is from an equilibrium of Eqs. (5)-(6), in the units of H: the
// |grad_d phi|^2-weighted standard deviation of H_mu = 3 sqrt2 nu / eps (as mean_curvature_mu)
// over the grid. At a discrete steady state nu = W'(phi) - eps^2 Lap_d phi is constant (the
// volume multiplier), so this is 0 there; away from it, it is the spread of the local mean
// curvature that the diffuse layer still drives (docs/method.md). 0 for a field without an
// interface. Needs ghost >= 2.
double equilibrium_residual(const Field& phi, double epsilon);
double equilibrium_residual_ref(const Field& phi, double epsilon);  // plain loop twin

// The sums of nu |grad_d phi|^2 and of |grad_d phi|^2 over the grid, from which
// mean_curvature_mu and equilibrium_residual start, and of (nu - shift)^2 |grad_d phi|^2 about a
// shift given beforehand (an estimate of their weighted mean: the last step's), from which
// the spread follows in the same pass (equilibrium_met).
struct WeightedNuSums {
  double nu_w = 0.0;
  double w = 0.0;
  double shift = 0.0;
  double shifted_w = 0.0;  // sum of (nu - shift)^2 |grad_d phi|^2
};
// equilibrium_residual's second pass, from sums a fused pass already took (step_measures).
double equilibrium_residual(const Field& phi, double epsilon, const WeightedNuSums& sums);
// equilibrium_residual from the shifted sums alone: the weighted variance
// shifted_w / w - (mean - shift)^2 in the units of H, or -1 where the shift lies more than one
// spread from the mean (the subtraction would then lose more than a bit).
double equilibrium_residual_one_pass(const WeightedNuSums& sums, double epsilon);
// Whether equilibrium_residual(phi, epsilon, sums) <= tol, mostly without its second pass: the
// one-pass value decides where it lies further than kOnePassMargin (relative) from tol, which
// is beyond its rounding difference from the two-pass value; otherwise the second pass runs.
// So the stop rule takes the same decisions, and the steps the same bits, as with two passes.
bool equilibrium_met(const Field& phi, double epsilon, const WeightedNuSums& sums, double tol);
constexpr double kOnePassMargin = 1e-6;

// What the time-step history records of each step, and the stop rule's first sums.
struct StepMeasures {
  double area = 0.0;
  double energy = 0.0;
  double mass = 0.0;
  double d_phi = 0.0;  // l2_diff(phi, before)
  double volume_fraction = 0.0;  // sharp_volume_fraction(phi)
  WeightedNuSums nu_sums;  // zero unless asked for
};
// area, energy, mass, l2_diff(phi, before), sharp_volume_fraction and, with nu_sums, the
// weighted sums of nu (WeightedNuSums), in one pass over phi instead of six: each value has the
// same bits as its own function's (each sum keeps its own order of additions). Needs ghost >= 2
// and a current halo; before: interior.
// nu_shift: the shift of nu_sums' shifted sum.
StepMeasures step_measures(const Field& phi, const Field& before, double epsilon, bool nu_sums,
                           double nu_shift = 0.0);
StepMeasures step_measures_ref(const Field& phi, const Field& before, double epsilon,
                               bool nu_sums, double nu_shift = 0.0);  // the separate functions

}  // namespace cmcsurf
