#include "cahn_hilliard/time_step.h"

#include <cmath>

#include <fmt/format.h>

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

ChStepperState ChStepper::take_state() {
  ChStepperState s;
  s.nu_valid = nu_valid_;
  if (nu_valid_) std::swap(s.nu, solver_.solution()[1]);
  s.history_valid = history_valid_;
  s.prev_dt = prev_dt_;
  if (history_valid_) {
    std::swap(s.prev_phi, prev_phi_);
    std::swap(s.prev_nu, prev_nu_);
  }
  return s;
}

void ChStepper::restore_state(ChStepperState&& s) {
  // A field moved out by take_state comes back by swap; one read from a checkpoint is copied
  // into the stepper's own (their ghost widths may differ).
  auto put = [](Field& from, Field& to) {
    if (to.n() == 0) {
      std::swap(from, to);
    } else {
      CMCSURF_CHECK(from.n() == to.n());
      copy_interior(from, to);
    }
  };
  result_valid_ = false;  // the solver's fields are not a step's any more
  nu_valid_ = s.nu_valid;
  if (s.nu_valid) {
    put(s.nu, solver_.solution()[1]);
    solver_.solution()[1].exchange_halo();
  }
  history_valid_ = s.history_valid;
  prev_dt_ = s.prev_dt;
  if (s.history_valid) {
    if (prev_phi_.n() == 0 && s.prev_phi.n() != 0 && s.prev_phi.ghost() != 0) {
      prev_phi_ = Field::like(s.prev_phi, 0);
      prev_nu_ = Field::like(s.prev_phi, 0);
    }
    put(s.prev_phi, prev_phi_);
    put(s.prev_nu, prev_nu_);
  }
}

void extrapolate_into(const Field& x, Field& prev, Field& guess, double r) {
  CMCSURF_CHECK(prev.size() == x.size() && guess.size() == x.size());
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

void extrapolate_into_ref(const Field& x, Field& prev, Field& guess, double r) {
  for_each_cell(x, [&](int i, int j, int k) {
    const double now = x(i, j, k), before = prev(i, j, k);
    prev(i, j, k) = now;
    guess(i, j, k) = now + r * (now - before);
  });
}

StepStats ChStepper::step(Field& phi) {
  Fields& u = solver_.solution();
  Fields& rhs = solver_.rhs();
  const ChParams& p = op_.params();
  result_valid_ = false;
  phi.exchange_halo();
  if (!nu_valid_) {
    ch_nu_from_phi(phi, p.epsilon, u[1]);
    nu_valid_ = true;
  }
  u[1].exchange_halo();
  // With extrapolation and no history (the first step, or after reset_nu), phi^n and nu^n
  // become the history: copied in the first pass below instead of two passes of their own.
  if (options_.extrapolate && prev_phi_.n() != phi.n()) {
    prev_phi_ = Field::like(phi, 0);
    prev_nu_ = Field::like(phi, 0);
    history_valid_ = false;
  }
  const bool history_in_first_pass = options_.extrapolate && !history_valid_;

  StepStats stats;
  // The source, phi^{n+1} started from phi^n, the defect of that guess and the mass of phi^n,
  // in one pass; u[0]'s ghosts are exchanged by whatever reads them next (the extrapolation's
  // norm, the V-cycle).
  double mass_n = 0.0;
  StepStartExtras extras;
  extras.phi_mean = &mass_n;
  if (history_in_first_pass) {
    extras.phi_copy = &prev_phi_;
    extras.nu_copy = &prev_nu_;
  }
  stats.first_residual = ch_source_first_defect(phi, u[1], p, rhs[0], rhs[1], u[0], extras);
  stats.residual = stats.first_residual;
  if (!std::isfinite(stats.first_residual))
    throw SolverDiverged(fmt::format(
        "the phase field or the time step's source is not finite (defect norm {}) on N = {}",
        stats.first_residual, phi.n()));
  // The mean of u[0], for the mass restore: each defect norm below takes it in its pass.
  double mass_u = mass_n;
  auto residual_norm = [&] {
    exchange_halos(u[0], u[1]);
    return nso_residual_norm_mean(u[0], u[1], rhs[0], rhs[1], p, mass_u);
  };
  const double target = std::max(options_.tol, options_.rtol * stats.first_residual);
  if (options_.extrapolate) {
    if (history_valid_ && stats.residual > target) {
      // u[1] holds nu^n: keep it in prev_nu_ while forming the guess in place.
      const double r = p.dt / prev_dt_;
      extrapolate_into(phi, prev_phi_, u[0], r);
      extrapolate_into(u[1], prev_nu_, u[1], r);
      const double e = residual_norm();
      if (std::isfinite(e) && e < stats.residual) {
        stats.residual = e;
      } else {  // a worse guess (the flow turned): back to phi^n, nu^n
        copy_interior(phi, u[0]);
        copy_interior(prev_nu_, u[1]);
        mass_u = mass_n;
      }
    } else if (!history_in_first_pass) {
      copy_interior(phi, prev_phi_);
      copy_interior(u[1], prev_nu_);
    }
    prev_dt_ = p.dt;
    history_valid_ = true;
  }
  while (stats.residual > target && stats.vcycles < options_.max_vcycles) {
    solver_.vcycle(op_);
    ++stats.vcycles;
    stats.residual = residual_norm();
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
  drift_ = options_.restore_mass ? mass_n - mass_u : 0.0;
  result_valid_ = true;
  rewrite_step_result(phi);
  return stats;
}

void ChStepper::rewrite_step_result(Field& phi) const {
  CMCSURF_CHECK(result_valid_);
  copy_interior_plus(solver_.solution()[0], drift_, phi);
  phi.exchange_halo();
}

void copy_interior_plus(const Field& src, double c, Field& dst) {
  CMCSURF_CHECK(src.size() == dst.size());
  if (c == 0.0) {
    copy_interior(src, dst);
    return;
  }
  const int nx = src.nx(), ny = src.ny(), nz = src.nz();
#pragma omp parallel for schedule(static) if (nx >= kParallelMinN)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      const double* s = &src(0, j, k);
      double* d = &dst(0, j, k);
#pragma omp simd
      for (int i = 0; i < nx; ++i) d[i] = s[i] + c;
    }
}

void copy_interior_plus_ref(const Field& src, double c, Field& dst) {
  copy_interior(src, dst);
  dst.exchange_halo();
  if (c != 0.0) add_constant(dst, c);
}

}  // namespace cmcsurf
