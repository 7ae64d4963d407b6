#include "pipeline/cmc.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "cahn_hilliard/anderson.h"
#include "common/wall_clock.h"
#include "measure/measures.h"
#include "multigrid/fas.h"
#include "pipeline/cell_geometry.h"
#include "pipeline/continuation.h"
#include "measure/sharp_surface.h"
#include "measure/sharp_volume.h"
#include "measure/components.h"
#include "measure/topology.h"
#include "measure/whole_surface.h"
#include "surfaces/initial.h"

namespace cmcsurf {

Measures measure_field_diffuse(Field& phi, double epsilon) {
  phi.exchange_halo();
  Measures m;
  m.area_diffuse = area(phi, epsilon);
  m.mean_curvature_diffuse = mean_curvature(phi);
  m.total_mean_curvature_diffuse = m.mean_curvature_diffuse * m.area_diffuse;
  m.mean_curvature_mu = mean_curvature_mu(phi, epsilon);
  m.volume_fraction = sharp_volume_fraction(phi);
  m.volume_fraction_cells = volume_fraction(phi);
  m.mass = mass(phi);
  m.energy = energy(phi, epsilon);
  m.equilibrium_residual = equilibrium_residual(phi, epsilon);
  return m;
}

namespace {

// Largest grid whose phase field a decomposed run gathers on every process to label the phases'
// components (8 MiB a process at 128^3); larger decomposed runs leave them unreported.
constexpr int kComponentsGatherMaxN = 128;

// The sharp measures into m, from phi (halo current) or, when given, from its psi.
void add_sharp_measures(Measures& m, const Field& phi, const Field* psi = nullptr,
                        std::vector<CurvatureSample>* samples = nullptr) {
  const SharpMeasures s = psi ? sharp_measures_psi(*psi, samples) : sharp_measures(phi, samples);
  m.area = s.area;
  m.area_error = s.area_error;
  m.mean_curvature = s.mean_curvature;
  m.mean_curvature_error = s.mean_curvature_error;
  m.mean_curvature_std = s.mean_curvature_std;
  m.total_mean_curvature = s.mean_curvature * s.area;
  m.gaussian_curvature_integral = s.gaussian_curvature_integral;
  m.willmore_energy = s.willmore_energy;
  m.euler_characteristic = euler_characteristic(phi);
  m.euler_characteristic_phase2 = euler_characteristic_phase2(phi);
  const auto d = phi.shared_decomposition();
  PhaseComponents c{-1, -1, -1};
  if (!d || !d->distributed()) {
    c = phase_components(phi);
  } else if (phi.n() <= kComponentsGatherMaxN) {
    Field whole(phi.n(), 1);
    gather_field(phi, whole, true);
    c = phase_components(whole);
  }
  m.components_phase1 = c.phase1;
  m.components_phase2 = c.phase2;
  m.surface_components = c.interfaces;
  m.sharp = true;
}

}  // namespace

Measures measure_field(Field& phi, double epsilon) {
  Measures m = measure_field_diffuse(phi, epsilon);
  add_sharp_measures(m, phi);
  return m;
}

double average_volume_fraction(const Field& phi, double alpha, double beta) {
  const int nx = phi.nx(), ny = phi.ny(), nz = phi.nz();
  const bool upper = alpha > 0.5;
  double sum = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : sum)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      const double* p = &phi(0, j, k);
      for (int i = 0; i < nx; ++i) {
        double v = p[i];
        if (upper && v > beta) v = 1.0;
        if (!upper && v < beta) v = 0.0;
        sum += v;
      }
    }
  return phi.sum_over_ranks(sum) / phi.global_cells();
}

BisectionResult bisect_threshold(const Field& phi, double alpha, double tol, int max_it) {
  auto f = [&](double beta) { return average_volume_fraction(phi, alpha, beta) - alpha; };
  BisectionResult r;
  r.beta = 0.0;
  double fa = f(0.0);
  r.iterations = 1;
  if (std::abs(fa) < tol) {
    r.v_ave = fa + alpha;
    return r;
  }
  double a = 0.0, b = 1.0;
  for (int k = 2; k <= max_it; ++k) {
    const double beta = a + (b - a) / 2;
    const double fp = f(beta);
    r.beta = beta;
    r.v_ave = fp + alpha;
    r.iterations = k;
    if (std::abs(fp) < tol || (b - a) / 2 < tol) return r;
    if (fa * fp > 0) {
      a = beta;
      fa = fp;
    } else {
      b = beta;
    }
  }
  return r;
}

void apply_threshold(Field& phi, double alpha, double beta) {
  const int nx = phi.nx(), ny = phi.ny(), nz = phi.nz();
  const bool upper = alpha > 0.5;
#pragma omp parallel for schedule(static)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      double* p = &phi(0, j, k);
      for (int i = 0; i < nx; ++i) {
        if (upper && p[i] > beta) p[i] = 1.0;
        if (!upper && p[i] < beta) p[i] = 0.0;
      }
    }
  phi.exchange_halo();
}

void truncate_unit_interval(Field& phi) {
  const int nx = phi.nx(), ny = phi.ny(), nz = phi.nz();
#pragma omp parallel for schedule(static)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      double* p = &phi(0, j, k);
      for (int i = 0; i < nx; ++i) p[i] = std::min(1.0, std::max(0.0, p[i]));
    }
  phi.exchange_halo();
}

void shift_mean(Field& phi, double alpha) {
  add_constant(phi, alpha - mass(phi));
  phi.exchange_halo();
}

std::string resume_problem(const Checkpoint& c, const RunParams& params, RunEntry entry,
                           const Decomposition* d) {
  const RunCursor& k = c.cursor;
  const RunResult& r = c.result;
  // The grids the run passes through, finest first (run_cmc_stages' rule), and its stages.
  const bool nodal = is_nodal_surface(params.surface);
  const bool direct = entry == RunEntry::kRelax || (entry == RunEntry::kCmc && !nodal);
  std::vector<int> grids = {params.grid};
  if (entry == RunEntry::kCmc && nodal)
    for (int g = params.grid, levels = params.coarse_levels;
         levels > 0 && check_coarsenable(g / 2).empty() && (!d || d->splits(g / 2));
         g /= 2, --levels)
      grids.push_back(g / 2);
  if (d && !d->splits(params.grid))
    return fmt::format("the run's grid {} cannot be split over {} processes", params.grid,
                       d->ranks());
  const auto at = std::find(grids.begin(), grids.end(), k.grid);
  if (at == grids.end())
    return fmt::format("the checkpoint's grid {} is not one this run passes through (grid {}, "
                       "{} coarse level(s) here)",
                       k.grid, params.grid, grids.size() - 1);
  const bool coarsest = at + 1 == grids.end();
  const bool prerelax_allowed = !direct && entry != RunEntry::kRelaxToVolume && coarsest;
  const bool volume_allowed = !direct && nodal && params.constrain == Constraint::kVolume;
  if (k.stage == RunStage::kPrerelax ? !prerelax_allowed
                                     : k.stage == RunStage::kVolume && !volume_allowed)
    return fmt::format("stage '{}' on grid {} is not one of this run's", run_stage_name(k.stage),
                       k.grid);
  if (r.phi.n() != k.grid || (c.stepper.nu_valid && c.stepper.nu.n() != k.grid) ||
      (c.stepper.history_valid &&
       (c.stepper.prev_phi.n() != k.grid || c.stepper.prev_nu.n() != k.grid)))
    return fmt::format("its fields are not on the stage's grid {}", k.grid);

  // Counts: the history holds every step; each counter lies within it.
  if (c.step < 0 || std::size_t(c.step) != r.history.size())
    return fmt::format("{} steps taken but {} in the history", c.step, r.history.size());
  long vcycles = 0;
  for (const StepRecord& s : r.history) {
    if (s.vcycles < 0 || s.vcycles > params.solver.max_vcycles)
      return fmt::format("step {} took {} V-cycles (limit {})", s.step, s.vcycles,
                         params.solver.max_vcycles);
    vcycles += s.vcycles;
  }
  if (r.vcycles != vcycles)
    return fmt::format("{} V-cycles counted, {} in the history", r.vcycles, vcycles);
  for (const int n : {r.steps, r.volume_steps, r.prerelax_steps, r.coarse_steps,
                      r.unconverged_steps, k.stage_steps})
    if (n < 0 || n > c.step)
      return fmt::format("a step count ({}) outside [0, {}] (the steps taken)", n, c.step);
  if (!(std::isfinite(c.time) && c.time >= 0.0) ||
      !(std::isfinite(c.elapsed) && c.elapsed >= 0.0 && c.elapsed <= 1e9))
    return fmt::format("model time {} or elapsed seconds {} out of range", c.time, c.elapsed);

  // The position inside the stage's loop: before one of its steps, with its time step.
  const double h = 1.0 / k.grid, dt0 = params.dt_factor * h;
  const double dt_max = std::max(dt0, params.dt_max_factor * h);
  const double slack = 1e-9 * dt0;  // dt is doubled and halved between dt0 and dt_max
  if (k.stage == RunStage::kPrerelax) {
    if (k.stage_steps >= params.prerelax_steps)
      return fmt::format("pre-relaxation step {} of {}", k.stage_steps, params.prerelax_steps);
    if (std::abs(k.dt - dt0) > slack)
      return fmt::format("pre-relaxation time step {} is not dt_factor h = {}", k.dt, dt0);
  } else {
    if (k.stage_steps >= params.max_steps)
      return fmt::format("{} step {} of at most {}", run_stage_name(k.stage), k.stage_steps,
                         params.max_steps);
    if (!(k.dt >= dt0 - slack && k.dt <= dt_max + slack))
      return fmt::format("time step {} outside [{}, {}] (dt_factor h, dt_max_factor h)", k.dt,
                         dt0, dt_max);
  }
  if (k.stage == RunStage::kVolume) {
    if (!r.volume_constrained || k.correction < 0 ||
        k.correction >= params.max_volume_corrections ||
        r.volume_iterates.size() != std::size_t(k.correction) + 1)
      return fmt::format("mass correction {} (at most {}) with {} volume iterates", k.correction,
                         params.max_volume_corrections, r.volume_iterates.size());
    if (!(k.slope >= 0.25 && k.slope <= 4.0) || !std::isfinite(k.volume))
      return fmt::format("secant slope {} outside [1/4, 4] or volume fraction {}", k.slope,
                         k.volume);
  } else if (r.volume_constrained || !r.volume_iterates.empty()) {
    return fmt::format("volume iterates before the volume stage ('{}')",
                       run_stage_name(k.stage));
  }

  // The mixer's history: only inside a relaxation that mixes, at this run's depth, on the
  // stage's grid (empty fields: a grid the decomposition does not split, named above).
  if (const std::optional<AndersonState>& m = c.anderson) {
    const bool mixes = k.stage != RunStage::kPrerelax && params.equilibrium_tol > 0.0 &&
                       params.anderson_depth > 0;
    if (!mixes)
      return fmt::format("it carries Anderson mixing history, but this run does not mix in "
                         "stage '{}' (anderson_depth {}, equilibrium_tol {})",
                         run_stage_name(k.stage), params.anderson_depth, params.equilibrium_tol);
    if (m->depth != AndersonMixer::effective_depth(params.anderson_depth))
      return fmt::format("its Anderson mixer has depth {}; this run's has {}", m->depth,
                         AndersonMixer::effective_depth(params.anderson_depth));
    const std::string problem = m->problem(r.phi.interior_size());
    if (!problem.empty()) return "its Anderson mixer: " + problem;
  }
  return {};
}

namespace {

// Refuses a checkpoint that `entry` cannot continue (instead of failing a CHECK inside).
void check_resumable(const RunParams& params, const RunContext& context, RunEntry entry) {
  if (!context.resume) return;
  const std::string problem =
      resume_problem(*context.resume, params, entry, context.decomposition.get());
  if (!problem.empty()) throw std::invalid_argument("cannot resume this checkpoint: " + problem);
}

// The time loop shared by the CMC algorithm and direct relaxations.
class Evolution {
 public:
  Evolution(const RunParams& params, const RunContext& context, RunResult& result)
      : params_(params),
        context_(context),
        progress_(context.progress),
        result_(result),
        stepper_(params.grid, {params.epsilon, params.dt(), params.smoother}, params.solver,
                 context.decomposition) {}

  void set_epsilon(double eps) { stepper_.set_params({eps, params_.dt(), params_.smoother}); }

  // Continues the step count, time and clock of an earlier (coarser) evolution.
  void continue_after(const RunResult& earlier, WallClock::time_point t0) {
    if (!earlier.history.empty()) {
      step_ = earlier.history.back().step;
      time_ = earlier.history.back().time;
    }
    t0_ = t0;
    continued_ = true;
  }

  // Continues from a checkpoint taken on this evolution's grid: its result so far, step count,
  // clock, stepper state and position (the stage loops pick up the position).
  void restore(const Checkpoint& c) {
    CMCSURF_CHECK(c.cursor.grid == params_.grid && c.result.phi.n() == params_.grid);
    Field phi = std::move(result_.phi);
    result_ = c.result;  // copies c's phi into a fresh field: put it into this run's own
    copy_interior(result_.phi, phi);
    result_.phi = std::move(phi);
    result_.phi.exchange_halo();
    step_ = c.step;
    time_ = c.time;
    last_step_converged_ = c.last_step_converged;
    t0_ = WallClock::now() - std::chrono::duration_cast<WallClock::duration>(
                             std::chrono::duration<double>(c.elapsed));
    cursor_ = c.cursor;
    const double eps = c.cursor.stage == RunStage::kPrerelax
                           ? params_.prerelax_epsilon_factor * params_.epsilon
                           : params_.epsilon;
    stepper_.set_params({eps, c.cursor.dt, params_.smoother});
    ChStepperState state = c.stepper;
    stepper_.restore_state(std::move(state));
    resumed_anderson_ = c.anderson;  // relax() takes it over once its mixer exists
    anderson_carried_ = c.anderson_carried;
    resuming_ = true;
  }

  // Whether this evolution continues a checkpoint taken in `stage` whose loop has not yet
  // picked it up.
  bool resuming(RunStage stage) const { return resuming_ && cursor_.stage == stage; }
  RunCursor& cursor() { return cursor_; }

  // Step 3: prerelax_steps steps at the wide epsilon.
  void prerelax() {
    const double wide = params_.prerelax_epsilon_factor * params_.epsilon;
    int first = 0;
    double a;
    if (resuming(RunStage::kPrerelax)) {
      first = cursor_.stage_steps;
      a = cursor_.area;
      resuming_ = false;
    } else {
      set_epsilon(wide);
      a = area(result_.phi, wide);
    }
    for (int s = first; s < params_.prerelax_steps; ++s) {
      mark(RunStage::kPrerelax, s, params_.dt(), a, 0.0);
      a = advance(RunStage::kPrerelax, a).area;
    }
    result_.prerelax_steps = params_.prerelax_steps;
  }

  // One step at the stepper's epsilon and dt, recorded in the history. With `equilibrium` the
  // record has the stop rule's residual (the history's pass takes its first sums).
  StepRecord advance(RunStage stage, double area_before, bool equilibrium = false) {
    Field& phi = result_.phi;
    const double eps = stepper_.params().epsilon;
    const double dt = stepper_.params().dt;
    // phi^n for d_phi: the stepper keeps it when it extrapolates, else a copy (one field of
    // N^3 less at the peak of a fast run).
    if (!stepper_.phi_before_step()) {
      if (previous_.n() != phi.n()) previous_ = Field::like(phi, 0);
      copy_interior(phi, previous_);
    }
    const auto ts = WallClock::now();
    const StepStats s = stepper_.step(phi);
    result_.solver_seconds += seconds_since(ts);
    project_components(phi);
    result_.vcycles += s.vcycles;
    last_step_converged_ = s.converged;
    if (!s.converged) ++result_.unconverged_steps;
    ++step_;
    time_ += dt;
    StepRecord r;
    r.step = step_;
    r.stage = stage;
    r.time = time_;
    r.dt = dt;
    // The equilibrium rule measures at params_.epsilon; the history's pass gives its sums
    // when the stepper is at that epsilon, with the spread about the last step's weighted
    // mean of nu (the shift), so that one pass mostly gives the residual.
    const bool nu_sums = equilibrium && eps == params_.epsilon;
    const double nu_shift =
        nu_sums_valid_ && last_nu_sums_.w > 0.0 ? last_nu_sums_.nu_w / last_nu_sums_.w : 0.0;
    nu_sums_valid_ = nu_sums;
    const StepMeasures m = step_measures(
        phi, stepper_.phi_before_step() ? *stepper_.phi_before_step() : previous_, eps,
        nu_sums, nu_shift);
    last_nu_sums_ = m.nu_sums;
    if (equilibrium) {
      // The history's value: the one-pass one where the shift allows it (within rounding of
      // the two passes', kOnePassMargin), else the two passes.
      const double one_pass =
          nu_sums ? equilibrium_residual_one_pass(m.nu_sums, params_.epsilon) : -1.0;
      r.equilibrium_residual =
          one_pass >= 0.0 ? one_pass
          : nu_sums       ? equilibrium_residual(phi, params_.epsilon, m.nu_sums)
                          : equilibrium_residual(phi, params_.epsilon);
      residual_exact_ = one_pass < 0.0;
    }
    r.area = m.area;
    r.d_area = r.area - area_before;
    r.d_phi = m.d_phi;
    r.energy = m.energy;
    r.mass = m.mass;
    r.volume_fraction = m.volume_fraction;
    r.vcycles = s.vcycles;
    r.residual = s.residual;
    r.elapsed = seconds_since(t0_);
    if (!std::isfinite(r.area) || !std::isfinite(r.mass))
      throw SolverDiverged("the phase field became non-finite at step " + std::to_string(step_));
    result_.history.push_back(r);
    if (progress_) progress_(r);
    return r;
  }

  // Step 6 (or the whole run for sphere/cube/noise, or a relaxation after a mass correction):
  // relax at epsilon until the stop rule; returns the steps taken.
  // With volume_rate > 0 the stop rule also needs the sharp volume fraction to change by at
  // most volume_rate in the step (after a mass correction the area can settle before V does).
  int relax(RunStage stage = RunStage::kRelax, double volume_rate = 0.0) {
    start_components();
    double a = 0.0, v = 0.0;
    if (!resuming(stage)) {
      set_epsilon(params_.epsilon);
      a = area(result_.phi, params_.epsilon);
      v = volume_rate > 0.0 ? sharp_volume_fraction(result_.phi) : 0.0;
    }
    result_.stop_reason = "max-steps";
    result_.converged = false;
    const double dt0 = params_.dt();
    const double dt_max = std::max(dt0, params_.dt_max_factor * params_.h());
    double dt = dt0;
    // A grid continued from a relaxed coarser field may skip the ramp from dt0: its steps at
    // the largest dt converge in one V-cycle each from the start (off by default: at 256^3 the
    // ramp's saved V-cycles came back as a longer tail of mixed steps).
    if (continued_ && stage == RunStage::kRelax && params_.continued_dt_factor > 0.0)
      dt = std::clamp(params_.continued_dt_factor * params_.h(), dt0, dt_max);
    continued_ = false;
    int taken = 0;
    const bool resumed = resuming(stage);
    if (resumed) {  // the checkpoint was taken inside this loop
      a = cursor_.area;
      v = cursor_.volume;
      dt = cursor_.dt;
      taken = cursor_.stage_steps;
      resuming_ = false;
    }
    const bool equilibrium = params_.equilibrium_tol > 0.0;
    // The mixing starts afresh with each relaxation (its map differs after a mass correction),
    // or goes on with the history the checkpoint carries.
    if (equilibrium && params_.anderson_depth > 0) {
      anderson_.emplace(params_.anderson_depth);
      if (resumed && resumed_anderson_) anderson_->restore_state(std::move(*resumed_anderson_));
      if (resumed && taken > 0 && !anderson_carried_)
        result_.warnings.push_back(fmt::format(
            "resumed from a checkpoint that predates the Anderson mixer's history (format 4 "
            "or 5): the mixing started afresh before step {}, so the run ends on the "
            "uninterrupted run's surface within the tolerance, not on its bits",
            step_ + 1));
    }
    resumed_anderson_.reset();
    for (int s = taken; s < params_.max_steps; ++s) {
      mark(stage, taken, dt, a, v);
      stepper_.set_dt(dt);
      const double step_dt = dt;
      const StepRecord r = advance(stage, a, equilibrium);
      dt = last_step_converged_ ? std::min(dt_max, 2.0 * dt) : std::max(dt0, 0.5 * dt);
      a = r.area;
      ++taken;
      ++result_.steps;
      bool met = params_.stop == StopRule::kArea ? std::abs(r.d_area) <= params_.tol
                                                 : r.d_phi <= params_.tol;
      if (equilibrium)  // instead of the --stop rule: the area settles before H equalises
        // The two passes' value decides as it is; a one-pass one near the tolerance is
        // checked by the two passes (equilibrium_met), so that the decisions are theirs.
        met = residual_exact_ ? r.equilibrium_residual <= params_.equilibrium_tol
                              : equilibrium_met(result_.phi, params_.epsilon, last_nu_sums_,
                                                params_.equilibrium_tol);
      if (volume_rate > 0.0) {
        met = met && std::abs(r.volume_fraction - v) <= volume_rate;
        v = r.volume_fraction;
      }
      if (met) {
        result_.converged = true;
        result_.stop_reason =
            equilibrium ? "equilibrium" : params_.stop == StopRule::kArea ? "area" : "phi";
        break;
      }
      if (params_.settle_tol > 0.0 && settled(taken)) {
        result_.converged = true;
        result_.stop_reason = "settled";
        break;
      }
      if (anderson_ && equilibrium) accelerate(step_dt == dt_max && dt == dt_max, r.energy);
    }
    anderson_.reset();  // its history (8 + 8 depth bytes per cell) is not needed after
    if (components_) components_->check_count(result_.phi, step_);
    result_.final = measure_field_diffuse(result_.phi, params_.epsilon);
    result_.wall_seconds = seconds_since(t0_);
    return taken;
  }

  // --constrain components: labels phase 1 where step 6 (or a resumed or finer grid's
  // relaxation) starts; its volume targets are kept in the result.
  void start_components() {
    if (params_.constrain != Constraint::kComponents || components_) return;
    if (!result_.phi.whole())
      throw std::invalid_argument("--constrain components: needs the whole grid on one process");
    result_.phi.exchange_halo();
    // A resumed run keeps the targets its checkpoint carries.
    components_.emplace(result_.phi, params_.volume_fraction, result_.component_volume_targets);
    result_.component_volume_targets = components_->targets();
  }

 private:
  // Each component back to its volume after a step; a count check every few steps (a merge
  // shows within them; the check labels the whole grid).
  void project_components(Field& phi) {
    if (!components_) return;
    constexpr int kCountCheckEvery = 10;
    components_->project(phi);
    if ((step_ + 1) % kCountCheckEvery == 0) components_->check_count(phi, step_ + 1);
  }

  // Mixes the field of the step just taken with the last ones at the same dt (the map
  // x -> G(x) is fixed only while dt is); any other step starts the history again.
  // energy_unmixed: the step's field's energy (its StepRecord's).
  void accelerate(bool fixed_dt, double energy_unmixed) {
    if (!fixed_dt) {
      anderson_->reset();
      return;
    }
    Field& phi = result_.phi;
    const Field* before = stepper_.phi_before_step();
    if (anderson_->mix(before ? *before : previous_, phi) > 0) {
      phi.exchange_halo();
      // The safeguard: the step map lowers the energy, and so does a mix that stays in its
      // basin. One that raises it has left it (measured: G at 0.5, 32^3, epsilon 0.96 h grew
      // new handles, chi -8 -> -32, without it); the step's own field is kept.
      if (energy(phi, stepper_.params().epsilon) > energy_unmixed) {
        // The stepper writes its step's field again, bit for bit, and the component
        // projection (deterministic) repeats what it did to it after the step.
        stepper_.rewrite_step_result(phi);
        if (components_) components_->project(phi);
        anderson_->reset();
        return;
      }
      // The stepper's nu and extrapolation history belong to the unmixed field; started
      // again from the mixed one, the next step takes fewer steps to the same end (13 finest
      // steps against 17 for G at 0.5, 128^3).
      stepper_.reset_nu();
    }
  }

  // Whether the diffuse area and the sharp volume fraction of the last `taken` steps (this
  // relaxation's) have settled within params.settle_tol (the history holds them, so that a
  // resumed run decides alike).
  bool settled(int taken) const {
    constexpr int kSeries = 4;
    if (taken < kSeries) return false;
    double areas[kSeries], volumes[kSeries];
    const auto& h = result_.history;
    for (int i = 0; i < kSeries; ++i) {
      const StepRecord& r = h[h.size() - kSeries + i];
      areas[i] = r.area;
      volumes[i] = r.volume_fraction;
    }
    return series_settled(areas, params_.settle_tol * std::abs(areas[kSeries - 1])) &&
           series_settled(volumes, params_.settle_tol);
  }

  // Records the position before a step, and asks the context whether to checkpoint or stop
  // there: a checkpoint lies between two steps, where the loops can pick it up (restore).
  void mark(RunStage stage, int stage_steps, double dt, double a, double v) {
    cursor_.grid = params_.grid;
    cursor_.stage = stage;
    cursor_.stage_steps = stage_steps;
    cursor_.dt = dt;
    cursor_.area = a;
    cursor_.volume = v;
    if (!context_.control) return;
    const RunControl control = context_.control();
    if (control == RunControl::kContinue) return;
    // The fields move into the checkpoint (no copy of the grid) and back after the call.
    Checkpoint c;
    Field phi = std::move(result_.phi);
    c.result = result_;
    c.result.phi = std::move(phi);
    c.result.wall_seconds = seconds_since(t0_);
    c.cursor = cursor_;
    c.step = step_;
    c.time = time_;
    c.last_step_converged = last_step_converged_;
    c.elapsed = seconds_since(t0_);
    c.stepper = stepper_.take_state();
    if (anderson_) c.anderson = anderson_->take_state();
    if (control == RunControl::kStop) throw RunInterrupted(std::move(c));
    struct Restore {  // also when the callback throws
      Checkpoint& c;
      Evolution& e;
      ~Restore() {
        e.result_.phi = std::move(c.result.phi);
        e.stepper_.restore_state(std::move(c.stepper));
        if (c.anderson) e.anderson_->restore_state(std::move(*c.anderson));
      }
    } restore{c, *this};
    if (context_.checkpoint) context_.checkpoint(c);
  }

  const RunParams& params_;
  const RunContext& context_;
  const ProgressFn& progress_;
  RunResult& result_;
  Field previous_;  // phi^n when the stepper does not keep it (allocated on first use)
  ChStepper stepper_;
  WallClock::time_point t0_ = WallClock::now();
  int step_ = 0;
  double time_ = 0.0;
  bool last_step_converged_ = true;
  bool continued_ = false;  // continue_after() and no relaxation since
  RunCursor cursor_;
  bool resuming_ = false;
  std::optional<ComponentConstraint> components_;
  std::optional<AndersonMixer> anderson_;
  // The last step's weighted sums of nu (step_measures), valid when it took them.
  WeightedNuSums last_nu_sums_;
  bool nu_sums_valid_ = false;
  bool residual_exact_ = true;  // the last record's equilibrium_residual is the two passes'
  // A checkpoint's mixer, until the relaxation it was taken in makes its own.
  std::optional<AndersonState> resumed_anderson_;
  bool anderson_carried_ = true;
};

// Constraint::kVolume after step 6: secant iteration on the mass m for V(m) = alpha, where
// V(m) is the sharp volume fraction after relaxing phi + (m - mass(phi)) from the last relaxed
// state. The first slope is 1 (a sharp interface between bulk phases 0 and 1 moves by the
// added mass); later slopes are secants, kept in [1/4, 4] against noise from the stop rule.
void constrain_volume(Evolution& evolution, const RunParams& params, RunResult& result) {
  const auto t0 = WallClock::now();
  const double alpha = params.volume_fraction;
  auto record = [&](int steps) {
    result.volume_iterates.push_back(
        {result.final.mass, result.final.volume_fraction, steps, result.converged});
  };
  auto within = [&] {
    return std::abs(result.volume_iterates.back().volume_fraction - alpha) <= params.volume_tol;
  };
  // A checkpoint taken during a correction's relaxation continues that relaxation: its mass
  // was corrected before the checkpoint.
  bool resuming = evolution.resuming(RunStage::kVolume);
  int first = 0;
  double slope = 1.0;
  if (resuming) {
    first = evolution.cursor().correction;
    slope = evolution.cursor().slope;
  } else {
    result.volume_constrained = true;
    record(result.steps);
  }
  for (int c = first; c < params.max_volume_corrections && (resuming || !within()); ++c) {
    if (!resuming) {
      const VolumeIterate& last = result.volume_iterates.back();
      if (result.volume_iterates.size() >= 2) {
        const VolumeIterate& prev = result.volume_iterates[result.volume_iterates.size() - 2];
        const double s = (last.volume_fraction - prev.volume_fraction) / (last.mass - prev.mass);
        if (std::isfinite(s)) slope = std::clamp(s, 0.25, 4.0);
      }
      const double target_mass = last.mass + (alpha - last.volume_fraction) / slope;
      add_constant(result.phi, target_mass - mass(result.phi));
      result.phi.exchange_halo();
    }
    resuming = false;
    evolution.cursor().correction = c;
    evolution.cursor().slope = slope;
    const int steps = evolution.relax(RunStage::kVolume, 0.01 * params.volume_tol);
    result.volume_steps += steps;
    record(steps);
  }
  result.volume_converged = within();
  result.volume_seconds += seconds_since(t0);
}

}  // namespace

namespace {

// Double structures: each piece of the surface, the components' volumes against their targets
// and the topology warnings (whole grids only: the labels are global).
void add_component_measures(RunResult& r) {
  if (!r.phi.whole()) return;
  // The whole surface's measures (add_sharp_measures, on this field): a bicontinuous surface
  // is one piece, measured once.
  const Measures& f = r.final;
  WholeSurfaceMeasures whole;
  whole.counts = {f.components_phase1, f.components_phase2, f.surface_components};
  whole.surface.area = f.area;
  whole.surface.mean_curvature = f.mean_curvature;
  whole.surface.mean_curvature_std = f.mean_curvature_std;
  whole.surface.gaussian_curvature_integral = f.gaussian_curvature_integral;
  whole.euler_phase1 = f.euler_characteristic;
  whole.euler_phase2 = f.euler_characteristic_phase2;
  whole.volume_fraction = f.volume_fraction;
  r.interfaces = interface_measures(r.phi, whole);
  if (!r.component_volume_targets.empty()) {
    r.component_volumes = component_volumes(r.phi, label_components(r.phi, 1));
  }
}

// The warnings of a finished run about its topology against its seed's.
void add_topology_warnings(RunResult& r, const RunParams& params) {
  if (r.seed_topology && r.final.sharp && r.final.components_phase1 >= 0) {
    for (std::string& w : topology_warnings(*r.seed_topology, phase_topology(r.final), params))
      r.warnings.push_back(std::move(w));
  }
}

}  // namespace

namespace {

// The sharp measures of the final field: once per run, after every stage.
void measure_final(RunResult& r, const RunParams& params, FinalFieldCache* cache) {
  const auto t0 = WallClock::now();
  // The diffuse measures are the last relaxation's (Evolution::relax ends with them, on this
  // field); the sharp ones are added.
  r.phi.exchange_halo();
  CMCSURF_DCHECK(r.final.mass == mass(r.phi) && r.final.energy == energy(r.phi, params.epsilon));
  // psi and the samples (this process's block's), kept in `cache` for the stages after the run.
  FinalFieldCache local;
  FinalFieldCache& keep = cache ? *cache : local;
  keep.psi = Field::like(r.phi, 2);
  tanh_profile_inverse(r.phi, keep.psi);
  keep.samples.clear();
  add_sharp_measures(r.final, r.phi, &keep.psi, &keep.samples);
  add_component_measures(r);
  r.measure_seconds = seconds_since(t0);
  if (!(r.final.area > 0.0))
    throw NoSurface(fmt::format(
        "the final field has no surface: phi > 1/2 {} (sharp volume fraction {:.6g}, target "
        "{:.6g}); a volume fraction too close to 0 or 1 for --grid {}, or a formula without a "
        "zero level, leaves no interface to relax",
        r.final.volume_fraction > 0.5 ? "everywhere" : "nowhere", r.final.volume_fraction,
        params.volume_fraction, params.grid));
  if (r.phi.whole()) {
    // The cell geometry costs several solves' worth at 128^3 (the exact distance to the mesh):
    // only when asked for, by a distance list or a lipid length.
    if (!params.parallel_distances.empty() || params.lipid_length > 0.0) {
      const SurfaceIntegrals s{r.final.area, r.final.total_mean_curvature,
                               r.final.euler_characteristic_surface()};
      r.geometry = measure_cell_geometry(keep.psi, s,
                                         parse_parallel_distances(params.parallel_distances),
                                         params.lipid_length, params.lipid_fraction);
    }
    if (params.distance_field) r.distance = profile_distance(keep.psi, params.epsilon);
    r.measure_seconds = seconds_since(t0);
  }
}

// Step 6 (unless a checkpoint was taken after it) and, with hold_volume, the volume
// constraint's corrections.
void relax_and_constrain(Evolution& evolution, const RunParams& params, RunResult& result,
                         bool hold_volume) {
  if (!evolution.resuming(RunStage::kVolume)) evolution.relax();
  if (hold_volume) constrain_volume(evolution, params, result);
}

// A result whose field is allocated for params.grid, and an evolution that continues the
// context's checkpoint, which was taken on this grid.
RunResult resumed_result(const RunParams& params, const RunContext& context) {
  CMCSURF_CHECK(context.resume && context.resume->cursor.grid == params.grid);
  RunResult result;
  result.phi = Field(params.grid, 2, context.decomposition);
  return result;
}

// A run that starts from a given field (copied), or continues the context's checkpoint:
// steps 6 and after, and the final measures.
RunResult relax_from(const Field& phi0, const RunParams& params, const RunContext& context,
                     bool hold_volume, FinalFieldCache* cache) {
  if (context.resume) {
    RunResult result = resumed_result(params, context);
    Evolution evolution(params, context, result);
    evolution.restore(*context.resume);
    relax_and_constrain(evolution, params, result, hold_volume);
    measure_final(result, params, cache);
    return result;
  }
  RunResult result;
  result.phi = Field(params.grid, 2, context.decomposition);
  copy_interior(phi0, result.phi);
  result.initial = measure_field(result.phi, params.epsilon);
  result.seed_topology = phase_topology(result.initial);
  Evolution evolution(params, context, result);
  relax_and_constrain(evolution, params, result, hold_volume);
  measure_final(result, params, cache);
  add_topology_warnings(result, params);
  return result;
}

// Steps 4 and 5: the bisection on beta, the threshold and the shift to mean alpha.
void threshold_and_shift(const RunParams& params, RunResult& result) {
  Field& phi = result.phi;
  result.bisection = bisect_threshold(phi, params.volume_fraction, params.bisection_tol,
                                      params.bisection_max_it);
  apply_threshold(phi, params.volume_fraction, result.bisection->beta);
  result.mass_before_shift = mass(phi);
  shift_mean(phi, params.volume_fraction);
}

RunResult run_cmc_stages(const RunParams& params, const RunContext& context,
                         const Field* start = nullptr);

}  // namespace

RunResult relax_field(const Field& phi0, const RunParams& params, const RunContext& context,
                      FinalFieldCache* cache) {
  check_resumable(params, context, RunEntry::kRelax);
  return relax_from(phi0, params, context, false, cache);
}

RunResult relax_to_volume_fraction(const Field& phi0, const RunParams& params,
                                   const RunContext& context, FinalFieldCache* cache) {
  check_resumable(params, context, RunEntry::kRelaxToVolume);
  const bool hold = params.constrain == Constraint::kVolume && is_nodal_surface(params.surface);
  return relax_from(phi0, params, context, hold, cache);
}

namespace {

// The settling tolerance of the coarser grids of a run that ends on the equilibrium rule: a
// backstop beside their own equilibrium rule (below), which stops them first in most runs.
constexpr double kCoarseSettleTol = 1e-5;

// Coarse-to-fine continuation: the whole algorithm on N/2, then the result interpolated to N
// and relaxed there (and volume-corrected), so most steps happen on the cheaper grid.
RunResult run_cmc_from_coarse(const RunParams& params, const RunContext& context) {
  const bool hold = params.constrain == Constraint::kVolume;
  // The finest grid starts from the relaxed coarse field: its V-cycles may stop at
  // mg_rtol_finest of each step's change; the coarse grids, where the run picks its branch,
  // keep mg_rtol.
  RunParams finest = params;
  if (params.mg_rtol_finest > 0.0) finest.solver.rtol = params.mg_rtol_finest;
  if (context.resume && context.resume->cursor.grid == params.grid) {
    // The checkpoint was taken on this grid: the coarse grids were done before it.
    RunResult result = resumed_result(finest, context);
    Evolution evolution(finest, context, result);
    evolution.restore(*context.resume);
    relax_and_constrain(evolution, finest, result, hold);
    return result;
  }
  // The clock of a run resumed on a coarser grid goes on from the checkpoint's.
  const auto t0 = WallClock::now() - std::chrono::duration_cast<WallClock::duration>(
                                     std::chrono::duration<double>(
                                         context.resume ? context.resume->elapsed : 0.0));
  RunParams coarse_params = params;
  coarse_params.grid = params.grid / 2;
  coarse_params.coarse_levels = params.coarse_levels - 1;
  coarse_params.mg_rtol_finest = 0.0;  // every coarser grid at mg_rtol
  if (params.equilibrium_tol > 0.0) {
    // A coarser grid only gives the finest its start, and its own equilibrium differs from the
    // finest's (epsilon is fewer cells wide there), but the nearer it comes to its own, the
    // fewer steps the finest takes: each coarser grid ends on the same rule at the same
    // tolerance, with the Anderson mixing that the rule brings. Ended on settling alone (the
    // rule until late on 2026-11-27), the unmixed steps crawled: P at 0.3, 128^3, took 165
    // steps on its 64^3 grid against 20, and the finest grid took no fewer steps for it; at 4
    // times the tolerance per halving the 256^3 grid took 82 steps for P, D, G at 0.3 and 0.5
    // against 67, one run each (docs/performance.md). The settling rule stays as a backstop.
    if (coarse_params.settle_tol == 0.0) coarse_params.settle_tol = kCoarseSettleTol;
  }
  RunResult coarse = run_cmc_stages(coarse_params, context);
  coarse.phi.exchange_halo();

  RunResult result;
  result.phi = Field(params.grid, 2, context.decomposition);
  prolongate_profile(coarse.phi, result.phi);
  coarse.phi = Field();  // an eighth of a field less while the finest grid relaxes
  result.history = coarse.history;
  for (StepRecord& r : result.history) r.coarse_grids.push_back(coarse_params.grid);
  result.coarse_steps = coarse.steps + coarse.prerelax_steps + coarse.coarse_steps;
  result.vcycles = coarse.vcycles;
  result.solver_seconds = coarse.solver_seconds;
  result.unconverged_steps = coarse.unconverged_steps;
  result.bisection = coarse.bisection;
  result.mass_before_shift = coarse.mass_before_shift;
  result.initial = coarse.initial;
  result.seed_topology = coarse.seed_topology;
  Evolution evolution(finest, context, result);
  evolution.continue_after(coarse, t0);
  relax_and_constrain(evolution, finest, result, hold);
  result.wall_seconds = seconds_since(t0);
  return result;
}

}  // namespace

namespace {

InitialFieldParams initial_field_params(const RunParams& params) {
  InitialFieldParams init;
  init.surface = params.surface;
  init.epsilon = params.epsilon;
  init.radius = params.radius;
  init.seed = params.seed;
  init.noise_amplitude = params.noise_amplitude;
  return init;
}

}  // namespace

RunResult run_cmc(const RunParams& params, const RunContext& context, FinalFieldCache* cache) {
  check_resumable(params, context, RunEntry::kCmc);
  if (!is_nodal_surface(params.surface)) {  // sphere, cube, noise: a direct relaxation
    if (context.resume) return relax_field(Field(), params, context, cache);
    return relax_field(make_initial_field(initial_field_params(params), params.grid, 2,
                                          context.decomposition),
                       params, context, cache);
  }
  RunResult result = run_cmc_stages(params, context);
  measure_final(result, params, cache);
  if (result.initial.sharp) result.euler_characteristic_start = result.initial.euler_characteristic;
  add_topology_warnings(result, params);
  return result;
}

RunResult run_cmc_from_field(const Field& phi0, const RunParams& params,
                             const RunContext& context, FinalFieldCache* cache) {
  check_resumable(params, context, RunEntry::kCmcFromField);
  RunResult result = run_cmc_stages(params, context, &phi0);
  measure_final(result, params, cache);
  if (result.initial.sharp) result.euler_characteristic_start = result.initial.euler_characteristic;
  add_topology_warnings(result, params);
  return result;
}

namespace {

// Steps 1-6 (and the volume constraint) for a nodal surface, without the final sharp measures;
// or the rest of them from the context's checkpoint.
RunResult run_cmc_stages(const RunParams& params, const RunContext& context,
                         const Field* start) {
  const auto& d = context.decomposition;
  if (!start && params.coarse_levels > 0 && check_coarsenable(params.grid / 2).empty() &&
      (!d || d->splits(params.grid / 2)))
    return run_cmc_from_coarse(params, context);

  RunResult result;
  if (context.resume) {
    result = resumed_result(params, context);
  } else {
    if (start) {  // step 1 given (run_cmc_from_field)
      result.phi = Field(params.grid, 2, d);
      copy_interior(*start, result.phi);
    } else if (params.structure == Structure::kDouble) {
      if (d && d->distributed())
        throw std::invalid_argument("--structure double: needs the whole grid on one process");
      result.phi = double_structure_seed(params);  // two networks at alpha, with the profile
    } else {
      result.phi = make_initial_field(initial_field_params(params), params.grid, 2, d);  // step 1
    }
    truncate_unit_interval(result.phi);                                                // step 2
    result.initial = measure_field(result.phi, params.epsilon);
    // What the result's topology is compared with: the nodal start {F > 0} (the family's,
    // as euler_characteristic_start) or the double seed; a checkpoint carries it.
    result.seed_topology = phase_topology(result.initial);
  }
  Evolution evolution(params, context, result);
  if (context.resume) evolution.restore(*context.resume);
  // A double seed is already at alpha with the equilibrium profile: the wide pre-relaxation
  // would dissolve its thin matrix and the threshold has nothing to do.
  const bool double_seed = params.structure == Structure::kDouble && !start;
  if (!evolution.resuming(RunStage::kRelax) && !evolution.resuming(RunStage::kVolume)) {
    if (!double_seed) {
      evolution.prerelax();                  // step 3
      threshold_and_shift(params, result);   // steps 4 and 5
    }
  }
  relax_and_constrain(evolution, params, result,
                      params.constrain == Constraint::kVolume);  // step 6 and after
  return result;
}

}  // namespace

}  // namespace cmcsurf
