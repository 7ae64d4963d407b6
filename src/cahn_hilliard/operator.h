// The discrete Cahn-Hilliard system of Eqs. (5)-(6) and its pointwise smoother (Appendix A).
//
//   NSO(phi, nu) = ( phi/dt - Lap_d nu ,  -f(phi) + eps^2 Lap_d phi + nu )
//   source       = ( phi^n/dt - 1/4 Lap_d phi^n ,  0 )
//   f(phi) = phi^3 - 3/2 phi^2 + 3/4 phi   (convex part of W', implicit)
//
// Time is scaled so that the mobility 6 sqrt2 M / eps is 1 (Section 3). The unknown nu is the
// convex-split chemical potential of Eq. (6), nu = f(phi) - eps^2 Lap_d phi: it holds only
// the implicit part of W' = f - phi/4, the explicit -phi^n/4 sits in the source as
// -1/4 Lap_d phi^n. So nu = eps/(6 sqrt2) mu + phi/4 (at a steady state, where
// phi^{n+1} = phi^n), not eps/(6 sqrt2) mu.
//
// Ghosts (docs/architecture.md): every kernel below that reads a field's neighbours requires
// its ghosts valid on entry (checked by CMCSURF_DCHECK in checked builds); right-hand sides,
// sources and outputs are interior-only fields unless a comment says otherwise.
#pragma once

#include "multigrid/fas.h"

namespace cmcsurf {

enum class SweepOrder { kRedBlack, kLexicographic };

struct ChParams {
  double epsilon = 0.01;
  double dt = 0.5 / 64;
  SweepOrder order = SweepOrder::kRedBlack;
};

inline double ch_f(double phi) { return phi * (phi * (phi - 1.5) + 0.75); }
inline double ch_df(double phi) { return phi * (3.0 * phi - 3.0) + 0.75; }

// One level's operator. Unknowns: u[0] = phi, u[1] = nu.
class ChOperator : public FasOperator {
 public:
  explicit ChOperator(const ChParams& p) : p_(p) {}
  const ChParams& params() const { return p_; }

  int components() const override { return 2; }
  void apply(const Fields& u, Fields& out) const override;
  void residual(const Fields& u, const Fields& rhs, Fields& out) const override;
  // Red-black (fused on a whole grid, colour by colour with exchanges on a block) or
  // lexicographic; u's ghosts are valid on return.
  void smooth(Fields& u, const Fields& rhs, int sweeps) const override;
  double norm(const Fields& defect) const override;  // ch_defect_norm
  double residual_norm(const Fields& u, const Fields& rhs, Fields& scratch) const override;
  void residual_restricted(const Fields& u, const Fields& rhs, Fields& scratch,
                           Fields& coarse) const override;

 private:
  ChParams p_;
};

// Source term (varphi^n, psi^n) of Appendix A from phi^n (ghosts of phi_n valid; writes the
// interiors of src_phi and src_nu).
void ch_source(const Field& phi_n, double dt, Field& src_phi, Field& src_nu);
void ch_source_ref(const Field& phi_n, double dt, Field& src_phi, Field& src_nu);

// nu = f(phi) - eps^2 Lap_d phi: Eq. (6) at phi, the first guess of nu^{n+1} (ghosts of phi
// valid; writes the interior of nu).
void ch_nu_from_phi(const Field& phi, double epsilon, Field& nu);

// The norm in which the V-cycles measure a defect (d_phi, d_nu) of Eqs. (5)-(6):
// sqrt(mean((dt d_phi)^2) + mean(d_nu^2)), both components in units of the unknowns
// (interiors only, summed over the processes).
double ch_defect_norm(const Field& d_phi, const Field& d_nu, double dt);
double ch_defect_norm_ref(const Field& d_phi, const Field& d_nu, double dt);

// Kernels, each with a plain reference twin for the tests. Ghosts of phi and nu must be valid;
// rhs and out are interior only. rhs == nullptr gives out = NSO(u); otherwise out = rhs - NSO(u).
void nso_residual(const Field& phi, const Field& nu, const Field* rhs_phi, const Field* rhs_nu,
                  const ChParams& p, Field& out_phi, Field& out_nu);
void nso_residual_ref(const Field& phi, const Field& nu, const Field* rhs_phi,
                      const Field* rhs_nu, const ChParams& p, Field& out_phi, Field& out_nu);

// ch_defect_norm(rhs - NSO(u)) without storing the defect: each row's defect goes to a buffer
// and is summed as ch_defect_norm sums it, so the result has the same bits as nso_residual
// followed by ch_defect_norm (a quarter of the bytes: no defect written and read back).
double nso_residual_norm(const Field& phi, const Field& nu, const Field& rhs_phi,
                         const Field& rhs_nu, const ChParams& p);
double nso_residual_norm_ref(const Field& phi, const Field& nu, const Field& rhs_phi,
                             const Field& rhs_nu, const ChParams& p);
// nso_residual_norm and, in the same pass, mean(phi) with mean's bits (the stepper's mass
// restore needs the mean of its last iterate, which the norm after each V-cycle reads anyway).
double nso_residual_norm_mean(const Field& phi, const Field& nu, const Field& rhs_phi,
                              const Field& rhs_nu, const ChParams& p, double& phi_mean);
double nso_residual_norm_mean_ref(const Field& phi, const Field& nu, const Field& rhs_phi,
                                  const Field& rhs_nu, const ChParams& p, double& phi_mean);

// The start of a time step in one pass: ch_source(phi_n, p.dt) into (src_phi, src_nu), phi_n's
// interior copied into guess, and the defect norm of (guess, nu) against that source, i.e.
// nso_residual_norm after the copy with guess's halo exchanged; the same bits as those three
// (the source rows are formed and read back while in cache). phi_n's and nu's ghosts must be
// valid; guess's ghosts are stale on return. The extras, each optional, come from the same
// pass: copies of phi_n's and nu's interiors (the stepper's extrapolation history, restarted)
// and mean(phi_n) with mean's bits (the mass the step restores).
struct StepStartExtras {
  Field* phi_copy = nullptr;
  Field* nu_copy = nullptr;
  double* phi_mean = nullptr;
};
double ch_source_first_defect(const Field& phi_n, const Field& nu, const ChParams& p,
                              Field& src_phi, Field& src_nu, Field& guess,
                              const StepStartExtras& extras = {});
double ch_source_first_defect_ref(const Field& phi_n, const Field& nu, const ChParams& p,
                                  Field& src_phi, Field& src_nu, Field& guess,
                                  const StepStartExtras& extras = {});

// restrict_average(rhs - NSO(u)) into the coarse fields (n/2, interiors) without storing the
// fine defect: the four fine rows under a coarse row are formed in buffers and averaged as
// restrict_average averages them, so the bits are those of nso_residual then restrict_average
// (the V-cycle saves writing two fine fields and reading them back).
void nso_residual_restrict(const Field& phi, const Field& nu, const Field& rhs_phi,
                           const Field& rhs_nu, const ChParams& p, Field& coarse_phi,
                           Field& coarse_nu);
void nso_residual_restrict_ref(const Field& phi, const Field& nu, const Field& rhs_phi,
                               const Field& rhs_nu, const ChParams& p, Field& coarse_phi,
                               Field& coarse_nu);

// One relaxation of the cells of one colour ((i+j+k) % 2 == colour, global indices) by
// (A.3)-(A.4), in parallel. Needs valid ghosts on entry and updates the interior only: the
// ghosts of phi and nu are stale on return, and the caller exchanges halos between colours.
void smooth_color(Field& phi, Field& nu, const Field& src_phi, const Field& src_nu,
                  const ChParams& p, int colour);
void smooth_color_ref(Field& phi, Field& nu, const Field& src_phi, const Field& src_nu,
                      const ChParams& p, int colour);

// `sweeps` whole red-black sweeps (colour 0, then colour 1, each sweep) in a single pass over
// memory, a wavefront in k: stage s (colour s % 2 of sweep s / 2) of plane k - s follows stage
// s - 1 of plane k - s + 1, with the periodic x/y ghosts of each plane refreshed after each
// stage and the z wrap at the end. Each thread takes a slab of at least 4 sweeps planes and
// finishes the planes around its first one after a barrier. Every cell sees the neighbour
// values it would see in smooth_color(0), smooth_color(1), ... with a halo exchange after each
// colour, so the results have the same bits for any thread count. Whole grids of even n only
// (throws std::logic_error on a block), n >= 4 sweeps when sweeps > 1. Needs valid ghosts on
// entry and leaves them valid.
void smooth_red_black_fused(Field& phi, Field& nu, const Field& src_phi, const Field& src_nu,
                            const ChParams& p, int sweeps = 1);

// One lexicographic Gauss-Seidel sweep exactly as printed in (A.3)-(A.4) (serial): the wrapped
// neighbours of the first cells are read from the ghosts as they were on entry. Whole grids
// only (throws std::logic_error on a block). Needs valid ghosts on entry and leaves them valid.
void smooth_lexicographic(Field& phi, Field& nu, const Field& src_phi, const Field& src_nu,
                          const ChParams& p);
void smooth_lexicographic_ref(Field& phi, Field& nu, const Field& src_phi, const Field& src_nu,
                              const ChParams& p);

}  // namespace cmcsurf
