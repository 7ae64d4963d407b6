#include "pipeline/cmc.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "measure/measures.h"
#include "multigrid/fas.h"
#include "measure/sharp_surface.h"
#include "measure/sharp_volume.h"
#include "surfaces/initial.h"

namespace cmcsurf {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace

const char* constraint_name(Constraint c) { return c == Constraint::kVolume ? "volume" : "mass"; }

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
  return m;
}

Measures measure_field(Field& phi, double epsilon) {
  Measures m = measure_field_diffuse(phi, epsilon);
  const SharpMeasures s = sharp_measures(phi);
  m.area = s.area;
  m.area_error = s.area_error;
  m.mean_curvature = s.mean_curvature;
  m.mean_curvature_error = s.mean_curvature_error;
  m.mean_curvature_std = s.mean_curvature_std;
  m.total_mean_curvature = s.mean_curvature * s.area;
  m.sharp = true;
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

namespace {

// The time loop shared by the CMC algorithm and direct relaxations.
class Evolution {
 public:
  Evolution(const RunParams& params, const RunContext& context, RunResult& result)
      : params_(params),
        progress_(context.progress),
        result_(result),
        previous_(params.grid, 2, context.decomposition),
        stepper_(params.grid, {params.epsilon, params.dt(), params.smoother}, params.solver,
                 context.decomposition) {}

  void set_epsilon(double eps) { stepper_.set_params({eps, params_.dt(), params_.smoother}); }

  // Continues the step count, time and clock of an earlier (coarser) evolution.
  void continue_after(const RunResult& earlier, Clock::time_point t0) {
    if (!earlier.history.empty()) {
      step_ = earlier.history.back().step;
      time_ = earlier.history.back().time;
    }
    t0_ = t0;
  }

  // One step at the stepper's epsilon and dt, recorded in the history.
  StepRecord advance(const char* stage, double area_before) {
    Field& phi = result_.phi;
    const double eps = stepper_.params().epsilon;
    const double dt = stepper_.params().dt;
    copy_interior(phi, previous_);
    const auto ts = Clock::now();
    const StepStats s = stepper_.step(phi);
    result_.solver_seconds += seconds_since(ts);
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
    r.area = area(phi, eps);
    r.d_area = r.area - area_before;
    r.d_phi = l2_diff(phi, previous_);
    r.energy = energy(phi, eps);
    r.mass = mass(phi);
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
  int relax(const char* stage = "relax", double volume_rate = 0.0) {
    set_epsilon(params_.epsilon);
    double a = area(result_.phi, params_.epsilon);
    double v = volume_rate > 0.0 ? sharp_volume_fraction(result_.phi) : 0.0;
    result_.stop_reason = "max-steps";
    result_.converged = false;
    const double dt0 = params_.dt();
    const double dt_max = std::max(dt0, params_.dt_max_factor * params_.h());
    double dt = dt0;
    int taken = 0;
    for (int s = 0; s < params_.max_steps; ++s) {
      stepper_.set_dt(dt);
      const StepRecord r = advance(stage, a);
      dt = last_step_converged_ ? std::min(dt_max, 2.0 * dt) : std::max(dt0, 0.5 * dt);
      a = r.area;
      ++taken;
      ++result_.steps;
      bool met = params_.stop == StopRule::kArea ? std::abs(r.d_area) <= params_.tol
                                                 : r.d_phi <= params_.tol;
      if (volume_rate > 0.0) {
        result_.phi.exchange_halo();
        const double v_new = sharp_volume_fraction(result_.phi);
        met = met && std::abs(v_new - v) <= volume_rate;
        v = v_new;
      }
      if (met) {
        result_.converged = true;
        result_.stop_reason = params_.stop == StopRule::kArea ? "area" : "phi";
        break;
      }
    }
    result_.final = measure_field_diffuse(result_.phi, params_.epsilon);
    result_.wall_seconds = seconds_since(t0_);
    return taken;
  }

 private:
  const RunParams& params_;
  const ProgressFn& progress_;
  RunResult& result_;
  Field previous_;
  ChStepper stepper_;
  Clock::time_point t0_ = Clock::now();
  int step_ = 0;
  double time_ = 0.0;
  bool last_step_converged_ = true;
};

// Constraint::kVolume after step 6: secant iteration on the mass m for V(m) = alpha, where
// V(m) is the sharp volume fraction after relaxing phi + (m - mass(phi)) from the last relaxed
// state. The first slope is 1 (a sharp interface between bulk phases 0 and 1 moves by the
// added mass); later slopes are secants, kept in [1/4, 4] against noise from the stop rule.
void constrain_volume(Evolution& evolution, const RunParams& params, RunResult& result) {
  const auto t0 = Clock::now();
  const double alpha = params.volume_fraction;
  auto record = [&](int steps) {
    result.volume_iterates.push_back(
        {result.final.mass, result.final.volume_fraction, steps, result.converged});
  };
  auto within = [&] {
    return std::abs(result.volume_iterates.back().volume_fraction - alpha) <= params.volume_tol;
  };
  result.volume_constrained = true;
  record(result.steps);
  double slope = 1.0;
  for (int c = 0; c < params.max_volume_corrections && !within(); ++c) {
    const VolumeIterate& last = result.volume_iterates.back();
    if (result.volume_iterates.size() >= 2) {
      const VolumeIterate& prev = result.volume_iterates[result.volume_iterates.size() - 2];
      const double s = (last.volume_fraction - prev.volume_fraction) / (last.mass - prev.mass);
      if (std::isfinite(s)) slope = std::clamp(s, 0.25, 4.0);
    }
    const double target_mass = last.mass + (alpha - last.volume_fraction) / slope;
    add_constant(result.phi, target_mass - mass(result.phi));
    result.phi.exchange_halo();
    const int steps = evolution.relax("volume", 0.01 * params.volume_tol);
    result.volume_steps += steps;
    record(steps);
  }
  result.volume_converged = within();
  result.volume_seconds = seconds_since(t0);
}

}  // namespace

namespace {

// The sharp measures of the final field: once per run, after every stage.
void measure_final(RunResult& r, const RunParams& params) {
  const auto t0 = Clock::now();
  r.final = measure_field(r.phi, params.epsilon);
  r.measure_seconds = seconds_since(t0);
}

RunResult run_cmc_stages(const RunParams& params, const RunContext& context);

// A run that starts from a given field (copied): steps 6 and after, and the final measures.
RunResult relax_from(const Field& phi0, const RunParams& params, const RunContext& context,
                     bool hold_volume) {
  RunResult result;
  result.phi = Field(params.grid, 2, context.decomposition);
  copy_interior(phi0, result.phi);
  result.initial = measure_field(result.phi, params.epsilon);
  Evolution evolution(params, context, result);
  evolution.relax();
  if (hold_volume) constrain_volume(evolution, params, result);
  measure_final(result, params);
  return result;
}

}  // namespace

RunResult relax_field(const Field& phi0, const RunParams& params, const RunContext& context) {
  return relax_from(phi0, params, context, false);
}

RunResult relax_to_volume_fraction(const Field& phi0, const RunParams& params,
                                   const RunContext& context) {
  const bool hold = params.constrain == Constraint::kVolume && is_nodal_surface(params.surface);
  return relax_from(phi0, params, context, hold);
}

namespace {

// Coarse-to-fine continuation: the whole algorithm on N/2, then the result interpolated to N
// and relaxed there (and volume-corrected), so most steps happen on the cheaper grid.
RunResult run_cmc_from_coarse(const RunParams& params, const RunContext& context) {
  const auto t0 = Clock::now();
  RunParams coarse_params = params;
  coarse_params.grid = params.grid / 2;
  coarse_params.coarse_levels = params.coarse_levels - 1;
  RunResult coarse = run_cmc_stages(coarse_params, context);
  coarse.phi.exchange_halo();

  RunResult result;
  result.phi = Field(params.grid, 2, context.decomposition);
  prolongate_trilinear(coarse.phi, result.phi);
  result.history = coarse.history;
  for (StepRecord& r : result.history) r.stage = fmt::format("{}@{}", r.stage, coarse_params.grid);
  result.coarse_steps = coarse.steps + coarse.prerelax_steps + coarse.coarse_steps;
  result.vcycles = coarse.vcycles;
  result.solver_seconds = coarse.solver_seconds;
  result.unconverged_steps = coarse.unconverged_steps;
  result.bisection = coarse.bisection;
  result.mass_before_shift = coarse.mass_before_shift;
  result.initial = coarse.initial;
  Evolution evolution(params, context, result);
  evolution.continue_after(coarse, t0);
  evolution.relax();
  if (params.constrain == Constraint::kVolume) constrain_volume(evolution, params, result);
  result.wall_seconds = seconds_since(t0);
  return result;
}

}  // namespace

void prolongate_trilinear(const Field& coarse, Field& fine) {
  // Cell-centred linear interpolation: a fine cell's centre lies a quarter of a coarse cell
  // from its parent's centre, so per axis the weights are 3/4 (parent) and 1/4 (neighbour).
  // Blocks: the fine block starts at twice the coarse block's offset (even), so i / 2 and
  // i % 2 hold for block indices too.
  const int nfx = fine.nx(), nfy = fine.ny(), nfz = fine.nz();
#pragma omp parallel for schedule(static) if (nfx >= kParallelMinN)
  for (int k = 0; k < nfz; ++k)
    for (int j = 0; j < nfy; ++j)
      for (int i = 0; i < nfx; ++i) {
        const int ci = i / 2, cj = j / 2, ck = k / 2;
        const int di = i % 2 ? 1 : -1, dj = j % 2 ? 1 : -1, dk = k % 2 ? 1 : -1;
        double v = 0.0;
        for (int c = 0; c < 8; ++c) {
          const int a = c & 1, b = (c >> 1) & 1, d = (c >> 2) & 1;
          const double w = (a ? 0.25 : 0.75) * (b ? 0.25 : 0.75) * (d ? 0.25 : 0.75);
          v += w * coarse(ci + a * di, cj + b * dj, ck + d * dk);
        }
        fine(i, j, k) = v;
      }
  fine.exchange_halo();
}

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

RunResult run_cmc(const RunParams& params, const RunContext& context) {
  if (!is_nodal_surface(params.surface))  // sphere, cube, noise: a direct relaxation
    return relax_field(make_initial_field(initial_field_params(params), params.grid, 2,
                                          context.decomposition),
                       params, context);
  RunResult result = run_cmc_stages(params, context);
  measure_final(result, params);
  return result;
}

namespace {

// Steps 1-6 (and the volume constraint) for a nodal surface, without the final sharp measures.
RunResult run_cmc_stages(const RunParams& params, const RunContext& context) {
  const InitialFieldParams init = initial_field_params(params);
  const auto& d = context.decomposition;
  if (params.coarse_levels > 0 && check_coarsenable(params.grid / 2).empty() &&
      (!d || d->splits(params.grid / 2)))
    return run_cmc_from_coarse(params, context);

  RunResult result;
  result.phi = make_initial_field(init, params.grid, 2, d);  // step 1
  Field& phi = result.phi;
  truncate_unit_interval(phi);  // step 2
  result.initial = measure_field(phi, params.epsilon);
  Evolution evolution(params, context, result);

  const double wide = params.prerelax_epsilon_factor * params.epsilon;  // step 3
  evolution.set_epsilon(wide);
  double a = area(phi, wide);
  for (int s = 0; s < params.prerelax_steps; ++s) a = evolution.advance("prerelax", a).area;
  result.prerelax_steps = params.prerelax_steps;

  result.bisection = bisect_threshold(phi, params.volume_fraction, params.bisection_tol,
                                      params.bisection_max_it);  // step 4
  apply_threshold(phi, params.volume_fraction, result.bisection->beta);
  result.mass_before_shift = mass(phi);
  shift_mean(phi, params.volume_fraction);  // step 5
  evolution.relax();                        // step 6
  if (params.constrain == Constraint::kVolume) constrain_volume(evolution, params, result);
  return result;
}

}  // namespace

}  // namespace cmcsurf
