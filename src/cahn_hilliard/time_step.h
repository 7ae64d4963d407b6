// One convex-splitting time step phi^n -> phi^{n+1} of Eqs. (5)-(6), solved by FAS V-cycles.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

#include "cahn_hilliard/operator.h"
#include "multigrid/fas.h"

namespace cmcsurf {

struct StepSolverOptions {
  FasOptions fas;
  double tol = 1e-9;      // stop V-cycles when the defect norm (ChOperator::norm) is below this
  // ... or below rtol times the step's first defect (0: off). The first defect measures how far
  // phi^n is from solving the new step, i.e. the step's change, so this stops each step at an
  // accuracy relative to what the step does (docs/performance.md).
  double rtol = 0.0;
  int max_vcycles = 100;  // per time step
  // Start each step from the linear extrapolation phi^n + (dt_n / dt_{n-1}) (phi^n - phi^{n-1})
  // (and the same for nu) instead of phi^n; rtol stays relative to the defect of phi^n, so a
  // better guess means fewer V-cycles. Off by default (the paper starts from phi^n).
  bool extrapolate = false;
  // A defect this many times above the step's first defect, or not finite, is divergence.
  double divergence_factor = 1e6;
  // After the V-cycles, add the constant that restores the mean of phi^n (the defect left at
  // the tolerance drifts the mass by up to tol per step). Tests turn it off to measure the
  // solver's own conservation.
  bool restore_mass = true;
};

// What a stepper carries from one step to the next: nu (the initial guess of mu's partner)
// and, with extrapolation, the previous step's phi, nu and dt. A checkpoint saves it so that a
// resumed run takes the same V-cycles as the uninterrupted one.
struct ChStepperState {
  Field nu;  // interior significant; empty when !nu_valid
  bool nu_valid = false;
  Field prev_phi, prev_nu;  // empty when !history_valid
  double prev_dt = 0.0;
  bool history_valid = false;
};

struct StepStats {
  int vcycles = 0;
  double residual = 0.0;      // defect norm after the last V-cycle
  double first_residual = 0.0;  // defect of phi^n as the guess (the step's change)
  bool converged = false;
};

// Thrown when the V-cycles diverge or produce NaN; what() is the diagnosis.
class SolverDiverged : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ChStepper {
 public:
  // decomposition: the processes sharing the grid (null: this process holds it whole).
  ChStepper(int n, const ChParams& params, const StepSolverOptions& options,
            std::shared_ptr<const Decomposition> decomposition = nullptr);

  const ChParams& params() const { return op_.params(); }
  void set_params(const ChParams& params);
  // Changes dt only: nu and the extrapolation history stay valid (adaptive time steps).
  void set_dt(double dt);

  // Advances phi by one step dt. Reads the interior of phi (its halo is exchanged on entry)
  // and leaves its ghosts valid. nu from the previous step is the initial guess; on the first
  // step or after reset_nu() it is initialised from phi.
  StepStats step(Field& phi);
  void reset_nu() {
    nu_valid_ = false;
    history_valid_ = false;
  }
  FasSolver& solver() { return solver_; }
  // With extrapolation, the stepper keeps phi^n through a step: after step() this is the phi it
  // started from (interior), so a caller need not copy it for ||phi^{n+1} - phi^n||. Null
  // without extrapolation.
  const Field* phi_before_step() const { return options_.extrapolate ? &prev_phi_ : nullptr; }
  // Writes the last step's phi^{n+1} into phi again (interior, halo exchanged): its solution
  // and mass shift are kept until the next step(), so a caller that changed phi after a step
  // (an Anderson mix it rejects) gets the step's field back without keeping a copy.
  void rewrite_step_result(Field& phi) const;
  // Moves the state out (no copy; the stepper is unusable until restore_state) ...
  ChStepperState take_state();
  // ... and back, or from a checkpoint (its fields' interiors are copied; any ghost width).
  void restore_state(ChStepperState&& state);

 private:
  ChOperator op_;
  StepSolverOptions options_;
  FasSolver solver_;
  bool nu_valid_ = false;
  // Extrapolation: phi^{n-1}, nu^{n-1} and dt_{n-1} (allocated on first use).
  Field prev_phi_, prev_nu_;
  double prev_dt_ = 0.0;
  bool history_valid_ = false;
  double drift_ = 0.0;  // the last step's mass shift (rewrite_step_result)
  bool result_valid_ = false;
};

// guess = x + r (x - prev) and then prev = x, cell by cell (x is phi^n or nu^n, prev the
// previous step's, r = dt_n / dt_{n-1}). Interiors only; guess may be x itself.
void extrapolate_into(const Field& x, Field& prev, Field& guess, double r);
void extrapolate_into_ref(const Field& x, Field& prev, Field& guess, double r);

// dst = src + c in the interior (dst's ghosts are not written), so that after dst's exchange
// it has the bits of copy_interior, exchange_halo and add_constant(dst, c): the step's end in
// one pass instead of three. c == 0 copies (-0.0 stays -0.0, as add_constant is then skipped).
void copy_interior_plus(const Field& src, double c, Field& dst);
void copy_interior_plus_ref(const Field& src, double c, Field& dst);

}  // namespace cmcsurf
