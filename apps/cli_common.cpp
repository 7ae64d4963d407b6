#include "cli_common.h"

#include <omp.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fmt/format.h>

#include "io/atomic_file.h"
#include "io/json_file.h"
#include "io/run_report.h"
#include "io/vti.h"
#include "multigrid/fas.h"
#include "pipeline/sweep.h"
#include "surfaces/initial.h"

namespace cmcsurf::cli {

std::string version_string() { return CMCSURF_VERSION; }

std::string plus_minus(double error) {
  return std::isfinite(error) ? fmt::format(" +- {:.1e}", error) : std::string();
}

void clear_run_outputs(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  // report.json first: from here until it is written again the folder reads as incomplete.
  std::vector<fs::path> stale = {dir / "report.json"};
  for (const char* name : {"field.vti", "history.csv", "curvature_histogram.csv"})
    stale.push_back(dir / name);
  for (const char* ext : {"stl", "ply", "obj", "3mf"}) {
    stale.push_back(dir / (std::string("surface.") + ext));
    stale.push_back(dir / (std::string("surface.") + ext + ".json"));
  }
  for (const fs::path& f : stale) {
    std::error_code ec;
    fs::remove(f, ec);
    if (ec)
      throw std::runtime_error(
          fmt::format("cannot remove the earlier run's '{}': {}", f.string(), ec.message()));
  }
}

nlohmann::json write_run_folder(const std::filesystem::path& dir, const RunParams& p,
                                const RunResult& r, const Field& phi, const CmcQuality& quality,
                                int threads, bool float32, const nlohmann::json& extra,
                                const std::function<void()>& extra_files) {
  nlohmann::json report = run_report(p, r, threads);
  report.update(quality_json(quality, r.final.area));
  if (extra.is_object()) report.update(extra);
  ensure_directory(dir);
  clear_run_outputs(dir);
  write_curvature_histogram_csv(dir / "curvature_histogram.csv", quality);
  write_history_csv(dir / "history.csv", r.history);
  const nlohmann::json& target = report["volume_fraction_target"];
  write_vti(dir / "field.vti", {{"phi", &phi}}, float32,
            {{"surface", p.surface},
             {"volume_fraction_target", target.is_null() ? "none" : fmt::format("{}", target.get<double>())},
             {"epsilon", fmt::format("{}", p.epsilon)},
             {"grid", fmt::format("{}", p.grid)},
             {"area", fmt::format("{:.17g}", r.final.area)},
             {"mean_curvature", fmt::format("{:.17g}", r.final.mean_curvature)},
             {"version", version_string()}});
  if (extra_files) extra_files();
  write_json_atomic(dir / "report.json", report);
  return report;
}

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
  app.add_option("--seed", p.seed, "Random seed (surface noise)")->capture_default_str();
  auto* g = app.add_option_group("solver", "Multigrid and algorithm details");
  g->add_option("--mg-tol", p.solver.tol,
                "V-cycles stop when the defect norm sqrt(mean (dt d_phi)^2 + mean d_nu^2) "
                "is below this")
      ->capture_default_str();
  app.add_flag("--fast", s.fast,
               "Fast mode: the options below marked (fast) take their fast values unless given "
               "(coarse-to-fine continuation, --mg-rtol 1e-2, --extrapolate, --dt-max-factor 8); "
               "the result agrees with the default paper-faithful run to about 1e-4 in area "
               "(docs/performance.md)");
  s.mg_rtol = g->add_option("--mg-rtol", p.solver.rtol,
                "(fast) Also stop V-cycles when the defect is below this times the step's first "
                "defect (0: off, the paper-faithful default; --fast uses 1e-2)")
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

namespace {

template <class T>
void require(bool ok, const char* option, T value, const char* accepted) {
  if (!ok) throw UsageError(fmt::format("{}: got {}; accepted: {}", option, value, accepted));
}

}  // namespace

int fast_coarse_levels(int grid) {
  int k = 0;
  while (k < 2 && (grid >> (k + 1)) >= 32 && check_coarsenable(grid >> (k + 1)).empty()) ++k;
  return k;
}

void finish_run_options(RunParams& p, const RunOptionStrings& s, bool check_surface) {
  if (s.fast) {
    p.fast = true;
    auto unset = [](const CLI::Option* o) { return o == nullptr || o->count() == 0; };
    if (unset(s.mg_rtol)) p.solver.rtol = kFastMgRtol;
    if (unset(s.dt_max_factor)) p.dt_max_factor = kFastDtMaxFactor;
    if (unset(s.extrapolate)) p.solver.extrapolate = true;
    if (unset(s.coarse_levels) && check_coarsenable(p.grid).empty())
      p.coarse_levels = fast_coarse_levels(p.grid);
  }
  if (s.stop == "area")
    p.stop = StopRule::kArea;
  else if (s.stop == "phi")
    p.stop = StopRule::kPhi;
  else
    throw UsageError(fmt::format("--stop: got '{}'; accepted: area, phi", s.stop));
  if (s.smoother == "redblack")
    p.smoother = SweepOrder::kRedBlack;
  else if (s.smoother == "lex")
    p.smoother = SweepOrder::kLexicographic;
  else
    throw UsageError(fmt::format("--smoother: got '{}'; accepted: redblack, lex", s.smoother));
  if (s.constrain == "volume")
    p.constrain = Constraint::kVolume;
  else if (s.constrain == "mass")
    p.constrain = Constraint::kMass;
  else
    throw UsageError(fmt::format("--constrain: got '{}'; accepted: volume, mass", s.constrain));

  if (check_surface) {
    try {
      validate_surface(p.surface);
    } catch (const std::invalid_argument& e) {
      throw UsageError(fmt::format("--surface: {}", e.what()));
    }
    require(p.volume_fraction > 0.0 && p.volume_fraction < 1.0, "--volume-fraction",
            p.volume_fraction, "0 < A < 1");
  }
  const std::string grid_problem = check_coarsenable(p.grid);
  if (!grid_problem.empty()) throw UsageError("--grid: " + grid_problem);
  require(p.grid <= 2048, "--grid", p.grid, "N <= 2048");
  require(p.epsilon > 0.0 && p.epsilon < 1.0, "--epsilon", p.epsilon, "0 < E < 1");
  require(p.dt_factor > 0.0 && std::isfinite(p.dt_factor), "--dt-factor", p.dt_factor,
          "C > 0 (dt = C h)");
  require(p.tol > 0.0, "--tol", p.tol, "T > 0");
  require(p.max_steps >= 1, "--max-steps", p.max_steps, "K >= 1");
  require(p.radius > 0.0 && p.radius < 0.5, "--radius", p.radius, "0 < R < 0.5");
  require(p.solver.tol > 0.0, "--mg-tol", p.solver.tol, "> 0");
  require(p.solver.rtol >= 0.0 && p.solver.rtol < 1.0, "--mg-rtol", p.solver.rtol, "0 <= R < 1");
  require(p.coarse_levels >= 0 && p.coarse_levels <= 4, "--coarse-levels", p.coarse_levels,
          "0..4");
  if (p.coarse_levels > 0 && !check_coarsenable(p.grid >> p.coarse_levels).empty())
    throw UsageError(fmt::format("--coarse-levels: {} halvings of --grid {} give {}, which {}",
                                 p.coarse_levels, p.grid, p.grid >> p.coarse_levels,
                                 check_coarsenable(p.grid >> p.coarse_levels)));
  require(p.dt_max_factor == 0.0 || (p.dt_max_factor >= p.dt_factor && p.dt_max_factor <= 1000.0),
          "--dt-max-factor", p.dt_max_factor, "0 (fixed dt) or --dt-factor <= F <= 1000");
  require(p.solver.max_vcycles >= 1, "--max-vcycles", p.solver.max_vcycles, ">= 1");
  require(p.solver.fas.pre_sweeps >= 0 && p.solver.fas.pre_sweeps <= 50, "--pre-sweeps",
          p.solver.fas.pre_sweeps, "0..50");
  require(p.solver.fas.post_sweeps >= 0 && p.solver.fas.post_sweeps <= 50, "--post-sweeps",
          p.solver.fas.post_sweeps, "0..50");
  require(p.solver.fas.pre_sweeps + p.solver.fas.post_sweeps >= 1, "--pre-sweeps/--post-sweeps",
          p.solver.fas.pre_sweeps + p.solver.fas.post_sweeps, "at least one sweep in total");
  require(p.prerelax_steps >= 0, "--prerelax-steps", p.prerelax_steps, ">= 0");
  require(p.prerelax_epsilon_factor > 0.0, "--prerelax-epsilon-factor",
          p.prerelax_epsilon_factor, "> 0");
  require(p.bisection_tol > 0.0, "--bisection-tol", p.bisection_tol, "> 0");
  require(p.bisection_max_it >= 1, "--bisection-max-it", p.bisection_max_it, ">= 1");
  require(p.volume_tol > 0.0 && p.volume_tol < 0.1, "--volume-tol", p.volume_tol, "0 < T < 0.1");
  require(p.max_volume_corrections >= 0 && p.max_volume_corrections <= 100,
          "--max-volume-corrections", p.max_volume_corrections, "0..100");
}

void add_threads_option(CLI::App& app, int& threads) {
  app.add_option("--threads", threads, "OpenMP threads (0: OMP_NUM_THREADS or all cores)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
}

int apply_threads(int threads) {
  if (threads > 0) omp_set_num_threads(threads);
  return omp_get_max_threads();
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
