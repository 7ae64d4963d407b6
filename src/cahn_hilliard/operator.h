// The discrete Cahn-Hilliard system of Eqs. (5)-(6) and its pointwise smoother (Appendix A).
//
//   NSO(phi, nu) = ( phi/dt - Lap_d nu ,  -f(phi) + eps^2 Lap_d phi + nu )
//   source       = ( phi^n/dt - 1/4 Lap_d phi^n ,  0 )
//   f(phi) = phi^3 - 3/2 phi^2 + 3/4 phi   (convex part of W', implicit)
//
// Time is scaled so that the mobility 6 sqrt2 M / eps is 1 (Section 3); nu = eps/(6 sqrt2) mu.
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
  void apply(Fields& u, Fields& out) const override;
  void residual(Fields& u, const Fields& rhs, Fields& out) const override;
  void smooth(Fields& u, const Fields& rhs, int sweeps) const override;
  // sqrt(mean((dt d_phi)^2) + mean(d_nu^2)): both components in units of the unknowns.
  double norm(const Fields& defect) const override;

 private:
  ChParams p_;
};

// Source term (varphi^n, psi^n) of Appendix A from phi^n (halo of phi_n must be current).
void ch_source(const Field& phi_n, double dt, Field& src_phi, Field& src_nu);

// Kernels, each with a plain reference twin for the tests. Halos of phi and nu must be current.
// rhs == nullptr gives out = NSO(u); otherwise out = rhs - NSO(u).
void nso_residual(const Field& phi, const Field& nu, const Field* rhs_phi, const Field* rhs_nu,
                  const ChParams& p, Field& out_phi, Field& out_nu);
void nso_residual_ref(const Field& phi, const Field& nu, const Field* rhs_phi,
                      const Field* rhs_nu, const ChParams& p, Field& out_phi, Field& out_nu);

// One relaxation of the cells of one colour ((i+j+k) % 2 == colour, global indices) by
// (A.3)-(A.4), in parallel; the caller exchanges halos between colours.
void smooth_color(Field& phi, Field& nu, const Field& src_phi, const Field& src_nu,
                  const ChParams& p, int colour);
void smooth_color_ref(Field& phi, Field& nu, const Field& src_phi, const Field& src_nu,
                      const ChParams& p, int colour);

// One whole red-black sweep (colour 0, then colour 1) in a single pass over memory: planes are
// visited once, colour 1 of plane k-1 right after colour 0 of plane k, with the periodic x/y
// ghosts of each plane refreshed in between and the z wrap at the end. Each thread takes a slab
// of planes and finishes its two boundary planes after a barrier. The arithmetic is that of
// smooth_color(0) then smooth_color(1) with a halo exchange between, so results are identical
// for any thread count. Needs a current halo on entry, a periodic single-block halo (no MPI
// neighbours) and even n; leaves the ghosts stale.
void smooth_red_black_fused(Field& phi, Field& nu, const Field& src_phi, const Field& src_nu,
                            const ChParams& p);

// One lexicographic Gauss-Seidel sweep exactly as printed in (A.3)-(A.4) (serial).
void smooth_lexicographic(Field& phi, Field& nu, const Field& src_phi, const Field& src_nu,
                          const ChParams& p);

}  // namespace cmcsurf
