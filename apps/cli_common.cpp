#include "cli_common.h"

#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <fmt/format.h>

#include "io/atomic_file.h"
#include "io/json_file.h"
#include "io/run_report.h"
#include "io/vti.h"
#include "multigrid/fas.h"
#include "parallel/decomposition.h"
#include "parallel/threads.h"
#include "pipeline/option_checks.h"
#include "pipeline/sweep.h"
#include "surfaces/initial.h"

namespace cmcsurf::cli {

std::string version_string() { return CMCSURF_VERSION; }

std::string plus_minus(double error) {
  return std::isfinite(error) ? fmt::format(" +- {:.1e}", error) : std::string();
}

namespace {

// An integer option's text through the library's check (pipeline/option_checks.h), so that
// Python says the same; text that is no integer is left to CLI11 ("Could not convert").
std::function<std::string(const std::string&)> library_check(std::string (*check)(long long)) {
  return [check](const std::string& text) -> std::string {
    errno = 0;
    char* end = nullptr;
    const long long v = std::strtoll(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0') return {};
    if (errno == ERANGE) {  // beyond long long; only a seed may still fit (unsigned 64 bits)
      errno = 0;
      std::strtoull(text.c_str(), nullptr, 10);
      if (errno == ERANGE || text.find('-') != std::string::npos)
        return fmt::format("got {}: beyond a 64-bit integer", text);
    }
    return check(v);  // clamped to long long: refused by the range check where it matters
  };
}

}  // namespace

void add_run_options(CLI::App& app, RunParams& p, RunOptionStrings& s, bool with_surface) {
  if (with_surface)
    app.add_option("--surface", p.surface,
                   "Initial surface: P, D, G (Eqs. 7-9), sphere, cube, noise, other nodal "
                   "surfaces (see `cmcsurf surfaces`)")
        ->capture_default_str();
  if (with_surface)
    app.add_option("--volume-fraction", p.volume_fraction,
                   "Target volume fraction alpha of phase 1 (phi > 1/2), in (0, 1)")
        ->capture_default_str();
  app.add_option("--grid", p.grid, "Cells per side N (m * 2^k, m in {1,3,5,7}, N >= 8)")
      ->capture_default_str();
  app.add_option("--epsilon", p.epsilon, "Interface parameter epsilon (> 0)")
      ->capture_default_str();
  app.add_option("--dt-factor", p.dt_factor, "Time step dt = C * h")->capture_default_str();
  app.add_option("--stop", s.stop,
                 "Stop rule: area (|A^{n+1} - A^n| <= tol, Section 4.5) or phi "
                 "(||phi^{n+1} - phi^n|| <= tol, Section 4.3)")
      ->capture_default_str();
  app.add_option("--tol", p.tol, "Tolerance of the stop rule")->capture_default_str();
  app.add_option("--max-steps", p.max_steps, "Limit on relaxation steps")->capture_default_str();
  app.add_option("--smoother", s.smoother,
                 "Gauss-Seidel ordering: redblack (parallel) or lex (as printed, serial)")
      ->capture_default_str();
  app.add_option("--constrain", s.constrain,
                 "What step 6 holds at --volume-fraction: volume (the sharp volume fraction of "
                 "phi > 1/2, by mass corrections after step 6) or mass (the paper's Section 4.4 "
                 "as printed); no effect for sphere, cube, noise")
      ->capture_default_str();
  app.add_option("--volume-tol", p.volume_tol,
                 "--constrain volume: stop correcting when |V - alpha| <= this")
      ->capture_default_str();
  app.add_option("--radius", p.radius, "Sphere radius (surface sphere), in (0, 0.5)")
      ->capture_default_str();
  app.add_option("--seed", p.seed, "Random seed (surface noise)")
      ->check(library_check(check_seed))
      ->capture_default_str();
  auto* g = app.add_option_group("solver", "Multigrid and algorithm details");
  g->add_option("--mg-tol", p.solver.tol,
                "V-cycles stop when the defect norm sqrt(mean (dt d_phi)^2 + mean d_nu^2) "
                "is below this")
      ->capture_default_str();
  app.add_flag("--fast", s.fast,
               "Fast mode: the options below marked (fast) take their fast values unless given "
               "(coarse-to-fine continuation, --mg-rtol 1e-2, --extrapolate, --dt-max-factor 8, "
               "--settle-tol 1e-5, --mg-rtol-finest 0.1); "
               "the result agrees with the default paper-faithful run to about 1e-4 in area "
               "(docs/performance.md)");
  s.mg_rtol = g->add_option("--mg-rtol", p.solver.rtol,
                "(fast) Also stop V-cycles when the defect is below this times the step's first "
                "defect (0: off, the paper-faithful default; --fast uses 1e-2)")
      ->capture_default_str();
  s.mg_rtol_finest = g->add_option("--mg-rtol-finest", p.mg_rtol_finest,
                "(fast) --mg-rtol on the finest grid of a coarse-to-fine run, which starts from "
                "the relaxed coarser field (0: --mg-rtol there too; --fast uses 0.1)")
      ->capture_default_str();
  s.coarse_levels = g->add_option("--coarse-levels", p.coarse_levels,
                "(fast) Coarse-to-fine continuation: run on N/2^K first, then interpolate and "
                "finish on each finer grid (0: off, the paper's procedure; --fast takes K <= 2 "
                "with N/2^K >= 32; nodal surfaces only)")
      ->capture_default_str();
  s.extrapolate = g->add_flag("--extrapolate,!--no-extrapolate", p.solver.extrapolate,
                "(fast) Start each step's V-cycles from the linear extrapolation of the last two "
                "steps instead of the last step");
  s.dt_max_factor = g->add_option("--dt-max-factor", p.dt_max_factor,
                "(fast) Adaptive time steps: during each relaxation at epsilon, dt doubles after "
                "every converged step up to this times h (0: fixed dt, the paper's; --fast uses 8)")
      ->capture_default_str();
  s.settle_tol = g->add_option("--settle-tol", p.settle_tol,
                "(fast) Also end each relaxation at epsilon once its diffuse area and sharp volume "
                "fraction have settled: their last two changes shrank and the geometric tail they "
                "predict is below this (relative to the area; absolute for the volume fraction). "
                "A steady drift, such as a slow pinch-off, never settles (0: off, the paper's "
                "rule alone; --fast uses 1e-5)")
      ->capture_default_str();
  g->add_option("--max-vcycles", p.solver.max_vcycles, "Limit on V-cycles per time step")
      ->capture_default_str();
  g->add_option("--pre-sweeps", p.solver.fas.pre_sweeps, "Presmoothing sweeps (beta)")
      ->capture_default_str();
  g->add_option("--post-sweeps", p.solver.fas.post_sweeps, "Postsmoothing sweeps (beta)")
      ->capture_default_str();
  g->add_option("--prerelax-steps", p.prerelax_steps, "Step 3: steps at the wide epsilon")
      ->capture_default_str();
  g->add_option("--prerelax-epsilon-factor", p.prerelax_epsilon_factor,
                "Step 3: wide epsilon = factor * epsilon")
      ->capture_default_str();
  g->add_option("--bisection-tol", p.bisection_tol, "Step 4: bisection tolerance")
      ->capture_default_str();
  g->add_option("--bisection-max-it", p.bisection_max_it, "Step 4: bisection iterations")
      ->capture_default_str();
  g->add_option("--max-volume-corrections", p.max_volume_corrections,
                "--constrain volume: limit on mass corrections (each one a relaxation)")
      ->capture_default_str();
}

void finish_run_options(RunParams& p, const RunOptionStrings& s, bool check_surface) {
  RunChoices c;
  c.stop = s.stop;
  c.smoother = s.smoother;
  c.constrain = s.constrain;
  c.fast = s.fast;
  auto given = [](const CLI::Option* o) { return o != nullptr && o->count() > 0; };
  c.mg_rtol_given = given(s.mg_rtol);
  c.coarse_levels_given = given(s.coarse_levels);
  c.dt_max_factor_given = given(s.dt_max_factor);
  c.settle_tol_given = given(s.settle_tol);
  c.mg_rtol_finest_given = given(s.mg_rtol_finest);
  c.extrapolate_given = given(s.extrapolate);
  try {
    finish_run_params(p, c, check_surface);
  } catch (const OptionError& e) {
    throw UsageError(e.what());
  }
}

void add_threads_option(CLI::App& app, int& threads) {
  app.add_option("--threads", threads,
                 "OpenMP threads per process (0: OMP_NUM_THREADS, else all cores or, under "
                 "mpirun, this rank's share of the cores it is bound to)")
      ->check(library_check(check_threads), "0 <= T <= " + std::to_string(kMaxThreads))
      ->capture_default_str();
}

int apply_threads(int threads) {
  const ThreadChoice choice = choose_threads(threads);  // parallel/threads.h
  if (!choice.warning.empty() && Decomposition::world()->rank() == 0)
    fmt::print(stderr, "warning: {}\n", choice.warning);
  return choice.threads;
}

Progress::Progress(bool quiet) : quiet_(quiet), tty_(isatty(fileno(stderr)) != 0) {}

void Progress::step(const StepRecord& r) {
  if (quiet_) return;
  last_ = r;
  last_printed_ = false;
  const bool new_stage = r.stage != last_stage_;
  const double interval = tty_ ? 0.1 : 5.0;
  if (!new_stage && r.elapsed - last_print_ < interval) return;
  print(r, new_stage);
}

void Progress::print(const StepRecord& r, bool new_stage) {
  last_print_ = r.elapsed;
  last_stage_ = r.stage;
  last_printed_ = true;
  const std::string line =
      fmt::format("{:<8} step {:>6}  t {:9.4f}  area {:.8f}  dA {:+.3e}  V-cycles {:>2}  {:7.1f} s",
                  r.stage, r.step, r.time, r.area, r.d_area, r.vcycles, r.elapsed);
  if (tty_) {
    if (new_stage && pending_newline_) std::fputc('\n', stderr);
    std::fprintf(stderr, "\r%s", line.c_str());
    pending_newline_ = true;
  } else {
    std::fprintf(stderr, "%s\n", line.c_str());
  }
  std::fflush(stderr);
}

void Progress::finish() {
  if (!quiet_ && !last_printed_) print(last_, last_.stage != last_stage_);
  if (pending_newline_) std::fputc('\n', stderr);
  pending_newline_ = false;
}

}  // namespace cmcsurf::cli
