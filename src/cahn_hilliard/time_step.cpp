#include "cahn_hilliard/time_step.h"

#include <cmath>

#include <fmt/format.h>

#include "grid/stencil.h"
#include "measure/measures.h"

namespace cmcsurf {


ChStepper::ChStepper(int n, const ChParams& params, const StepSolverOptions& options,
                     std::shared_ptr<const Decomposition> decomposition)
    : op_(params), options_(options), solver_(n, 2, 1, options.fas, std::move(decomposition)) {}

void ChStepper::set_params(const ChParams& params) {
  op_ = ChOperator(params);
  reset_nu();
}

void ChStepper::set_dt(double dt) {
  ChParams p = op_.params();
  p.dt = dt;
  op_ = ChOperator(p);
}

namespace {

// guess = x + r (x - prev) and prev = x, cell by cell (x is phi^n or nu^n).
void extrapolate_into(const Field& x, Field& prev, Field& guess, double r) {
  const int nx = x.nx(), ny = x.ny(), nz = x.nz();
#pragma omp parallel for schedule(static) if (nx >= kParallelMinN)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      const double* xr = &x(0, j, k);
      double* pr = &prev(0, j, k);
      double* gr = &guess(0, j, k);
      for (int i = 0; i < nx; ++i) {
        const double v = xr[i];
        gr[i] = v + r * (v - pr[i]);
        pr[i] = v;
      }
    }
}

}  // namespace

StepStats ChStepper::step(Field& phi) {
  Fields& u = solver_.solution();
  Fields& rhs = solver_.rhs();
  const ChParams& p = op_.params();
  phi.exchange_halo();
  ch_source(phi, p.dt, rhs[0], rhs[1]);
  copy_interior(phi, u[0]);  // phi^{n+1} starts from phi^n
  if (!nu_valid_) {
    // nu = f(phi) - eps^2 Lap phi: Eq. (6) at phi^n.
    u[0].exchange_halo();
    const int n = phi.n(), nx = phi.nx(), ny = phi.ny(), nz = phi.nz();
    const double inv_h2 = double(n) * n, eps2 = p.epsilon * p.epsilon;
    const std::ptrdiff_t sy = u[0].stride_y(), sz = u[0].stride_z();
#pragma omp parallel for schedule(static) if (nx >= kParallelMinN)
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j) {
        const double* ph = &u[0](0, j, k);
        double* nv = &u[1](0, j, k);
        for (int i = 0; i < nx; ++i)
          nv[i] = ch_f(ph[i]) - eps2 * laplacian(ph + i, sy, sz, inv_h2);
      }
    nu_valid_ = true;
  }

  StepStats stats;
  stats.first_residual = solver_.residual_norm(op_);
  stats.residual = stats.first_residual;
  if (!std::isfinite(stats.first_residual))
    throw SolverDiverged(fmt::format(
        "the phase field or the time step's source is not finite (defect norm {}) on N = {}",
        stats.first_residual, phi.n()));
  const double target = std::max(options_.tol, options_.rtol * stats.first_residual);
  if (options_.extrapolate) {
    if (prev_phi_.n() != phi.n()) {
      prev_phi_ = Field::like(phi, 0);
      prev_nu_ = Field::like(phi, 0);
      history_valid_ = false;
    }
    if (history_valid_ && stats.residual > target) {
      // u[1] holds nu^n: keep it in prev_nu_ while forming the guess in place.
      const double r = p.dt / prev_dt_;
      extrapolate_into(phi, prev_phi_, u[0], r);
      extrapolate_into(u[1], prev_nu_, u[1], r);
      const double e = solver_.residual_norm(op_);
      if (std::isfinite(e) && e < stats.residual) {
        stats.residual = e;
      } else {  // a worse guess (the flow turned): back to phi^n, nu^n
        copy_interior(phi, u[0]);
        copy_interior(prev_nu_, u[1]);
      }
    } else {
      copy_interior(phi, prev_phi_);
      copy_interior(u[1], prev_nu_);
    }
    prev_dt_ = p.dt;
    history_valid_ = true;
  }
  while (stats.residual > target && stats.vcycles < options_.max_vcycles) {
    solver_.vcycle(op_);
    ++stats.vcycles;
    stats.residual = solver_.residual_norm(op_);
    if (!std::isfinite(stats.residual) ||
        stats.residual > options_.divergence_factor * std::max(stats.first_residual, 1e-300)) {
      throw SolverDiverged(fmt::format(
          "multigrid diverged: defect norm {:.3e} after {} V-cycles (first {:.3e}); "
          "dt = {:.3e}, epsilon = {:.3e}, N = {}. A smaller --dt-factor or a larger "
          "--epsilon (at least about 2 cells, see docs) usually cures this",
          stats.residual, stats.vcycles, stats.first_residual, p.dt, p.epsilon, phi.n()));
    }
  }
  stats.converged = stats.residual <= target;
  // The exact discrete solution conserves mass (the periodic Laplacians sum to zero), but the
  // defect of Eq. (5) left at the tolerance has a mean of dt * mean(d_phi) that would drift the
  // mass by up to mg_tol per step. Removing the constant mode of that defect restores
  // conservation to round-off and changes the other defects far below the tolerance.
  const double drift = mass(phi) - mass(u[0]);
  copy_interior(u[0], phi);
  add_constant(phi, drift);
  phi.exchange_halo();
  return stats;
}

}  // namespace cmcsurf
