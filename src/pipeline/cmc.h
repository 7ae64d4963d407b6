// The CMC algorithm of Section 4.4 (steps 1-6) and direct relaxation of sphere/cube/noise.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "cahn_hilliard/time_step.h"
#include "grid/field.h"
#include "measure/sharp_surface.h"
#include "model/run.h"
#include "pipeline/component_constraint.h"
#include "pipeline/continuation.h"
#include "schema/report_schema.h"

namespace cmcsurf {

// Every measure, the sharp ones included (one extra pass over the grid and one over the
// surface). phi needs ghost >= 2; its halo is refreshed here.
Measures measure_field(Field& phi, double epsilon);
// The measures a relaxation needs as it goes: all but the sharp ones.
Measures measure_field_diffuse(Field& phi, double epsilon);

// Called after every time step with the step's record.
using ProgressFn = std::function<void(const StepRecord&)>;

enum class RunControl { kContinue, kCheckpoint, kStop };

// Thrown when a run's final field has no phi = 1/2 surface (the whole cell in one phase): a
// result with area 0 is not a CMC surface, whatever the stop rule said.
class NoSurface : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Thrown by a run whose RunContext::control said kStop before a time step; carries the
// checkpoint of that moment (the run's result so far is in it).
class RunInterrupted : public std::runtime_error {
 public:
  explicit RunInterrupted(Checkpoint c)
      : std::runtime_error("the run was interrupted"), checkpoint(std::move(c)) {}
  Checkpoint checkpoint;
};

// The run-time handles of a run, apart from its configuration (RunParams): neither changes the
// surface a run computes (docs/architecture.md). A progress function converts to a context.
struct RunContext {
  RunContext() = default;
  template <class F>
    requires(std::is_constructible_v<ProgressFn, F> &&
             !std::is_same_v<std::decay_t<F>, RunContext>)
  RunContext(F&& progress_fn) : progress(std::forward<F>(progress_fn)) {}  // NOLINT: implicit
  ProgressFn progress;  // after every time step (may be empty)
  // The processes sharing the grid (null: this process holds it whole). A run gives the same
  // surface on any number of processes (docs/scaling.md).
  std::shared_ptr<const Decomposition> decomposition;
  // Asked before every time step (may be empty): kCheckpoint calls `checkpoint` with the
  // state at that moment (valid during the call only), kStop throws RunInterrupted carrying
  // it. Under a decomposition every process must give the same answer at the same step.
  std::function<RunControl()> control;
  std::function<void(const Checkpoint&)> checkpoint;
  // Continue from this checkpoint instead of starting (the caller checks that it belongs to
  // the run's parameters; its fields are this process's blocks).
  std::shared_ptr<const Checkpoint> resume;
};

// Which entry point continues a checkpoint: run_cmc, run_cmc_from_field, relax_field or
// relax_to_volume_fraction (a sweep's continued member).
enum class RunEntry { kCmc, kCmcFromField, kRelax, kRelaxToVolume };

// Why `c` cannot be continued by `entry` with `params` on `decomposition` (null: one process
// holds the grid), or "" when it can: its cursor must stand on a grid and in a stage that run
// passes through (the coarse levels of the continuation, N >> k, k <= coarse_levels; the stages
// of that grid), with its counts inside the run's limits (steps, corrections, dt between dt_factor
// h and dt_max_factor h) and the result so far consistent with them (the history holds every
// step, a "volume" stage its iterates). A file that passed read_checkpoint's checks can still
// fail these; the entry points throw std::invalid_argument with this message.
std::string resume_problem(const Checkpoint& c, const RunParams& params, RunEntry entry,
                           const Decomposition* decomposition = nullptr);

// Section 4.4: V_ave(phi, alpha, beta).
double average_volume_fraction(const Field& phi, double alpha, double beta);
// Section 4.4's bisection on beta in [0, 1] for V_ave(phi, alpha, beta) = alpha, as printed.
BisectionResult bisect_threshold(const Field& phi, double alpha, double tol, int max_it);
// Step 4: phi = 1 where phi > beta (alpha > 0.5) or phi = 0 where phi < beta (alpha <= 0.5).
void apply_threshold(Field& phi, double alpha, double beta);
// Step 2: clamp to [0, 1].
void truncate_unit_interval(Field& phi);
// Step 5: phi += alpha - mean(phi).
void shift_mean(Field& phi, double alpha);

// Relaxes a given field (copied, any ghost width) at params.epsilon until the stop rule.
// Each entry point fills `cache` (if given) with the final measures' psi and samples.
RunResult relax_field(const Field& phi0, const RunParams& params, const RunContext& context = {},
                      FinalFieldCache* cache = nullptr);

// Steps 6 and after from a given start (copied): relaxes at params.epsilon and, for a nodal
// surface with Constraint::kVolume, corrects the mass until the sharp volume fraction is
// params.volume_fraction (the same secant iteration as run_cmc). Sweeps continue a family
// from its previous member with it.
RunResult relax_to_volume_fraction(const Field& phi0, const RunParams& params,
                                   const RunContext& context = {},
                                   FinalFieldCache* cache = nullptr);

// Runs the whole algorithm. Throws SolverDiverged on divergence, std::invalid_argument on
// parameters the caller should have validated.
RunResult run_cmc(const RunParams& params, const RunContext& context = {},
                  FinalFieldCache* cache = nullptr);

// Steps 2-6 and the volume constraint (Section 4.4) from a given phi^0 (copied, any ghost width)
// instead of the surface's formula, then the final measures, as run_cmc: a user's own field
// relaxed to the CMC surface at params.volume_fraction (python relax()). No coarse-to-fine
// continuation (params.coarse_levels is ignored: there is no coarser version of the field).
RunResult run_cmc_from_field(const Field& phi0, const RunParams& params,
                             const RunContext& context = {}, FinalFieldCache* cache = nullptr);

}  // namespace cmcsurf
