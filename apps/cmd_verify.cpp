// cmcsurf verify: the paper's verification experiments beside the paper's numbers, each with
// pass/fail checks (pipeline/verify.h); exit code 1 when a check fails.
#include <fmt/format.h>

#include <cmath>
#include <iostream>

#include "cli_common.h"
#include "commands.h"
#include "model/run_options.h"
#include "pipeline/verify.h"

namespace cmcsurf::cli {

namespace {

struct VerifyCommand {
  bool with_256 = false;
  bool quick = false;
  bool quiet = false;
  int threads = 0;
  int transition_grid = 64;
  int cube_grid = 64;
  int cube_steps = 400;
  int sphere_max_steps = 20000;
  std::string only;
};

// Prints the checks; returns how many failed.
int print_checks(const std::vector<VerifyCheck>& checks) {
  int failed = 0;
  for (const VerifyCheck& c : checks) {
    const bool ok = c.passed();
    failed += !ok;
    const std::string range =
        std::isinf(c.hi) ? fmt::format(">= {:.4g}", c.lo)
                         : fmt::format("[{:.5g}, {:.5g}]", c.lo, c.hi);
    fmt::print("  {} {:<40} {:>10.5g}  expected {:<9.5g} accepted {:<20} ({})\n",
               ok ? "PASS" : "FAIL", c.name, c.value, c.expected, range, c.basis);
  }
  return failed;
}

int print_transition(const VerifyCommand& c) {
  fmt::print("\n== Section 4.1: transition layer width for epsilon_m ==\n");
  fmt::print("phi(x,0) = 0.5 + 0.01 rand(x) on {}^3 (constant in y, z), dt = 0.05, t = 10\n",
             c.transition_grid);
  fmt::print("{:>3} {:>10} {:>10} {:>26} {:>9} {:>24} {:>9}\n", "m", "epsilon_m", "formed/all",
             "0.1->0.9 width (cells)", "expected", "0.05->0.95 width (cells)", "expected");
  std::vector<VerifyCheck> checks;
  // --quick: m = 8 only; at 32^3 the m = 4 run still has domains only a few layer widths wide
  // at t = 10, whose overlapping tails widen the layers (docs/verification.md).
  for (int m : {4, 8}) {
    if (c.quick && m != 8) continue;
    Progress progress(c.quiet);
    const auto r = verify_transition_layer(m, c.transition_grid, 10.0, 1,
                                           [&](const StepRecord& s) { progress.step(s); });
    progress.finish();
    fmt::print("{:>3} {:>10.6f} {:>10} {:>8.3f} [{:>6.2f}, {:>6.2f}] {:>9.3f} {:>24.3f} {:>9}\n", m,
               r.epsilon, fmt::format("{}/{}", r.interfaces, r.crossings), r.mean_width_cells,
               r.min_width_cells, r.max_width_cells, m * std::atanh(0.8) / std::atanh(0.9),
               r.mean_width_cells_05, m);
    for (VerifyCheck& check : transition_checks(r)) checks.push_back(std::move(check));
  }
  fmt::print("paper (Fig. 5, m = 4): the layer from 0.1 to 0.9 spans about 4 grid points\n");
  return print_checks(checks);
}

int print_cube(const VerifyCommand& c) {
  const int n = c.cube_grid;
  const double epsilon = 0.015;  // the paper's, on any grid
  fmt::print("\n== Section 4.2: a cube relaxes toward a sphere ==\n");
  fmt::print("{}^3, h = 1/{}, dt = h, epsilon = {}, up to {} steps (stop ||dphi|| <= 1e-5)\n",
             n, n, epsilon, c.cube_steps);
  Progress progress(c.quiet);
  const auto r = verify_cube_to_sphere(n, epsilon, c.cube_steps, 1e-5,
                                       [&](const StepRecord& s) { progress.step(s); });
  progress.finish();
  fmt::print("{:<34} {:>10} {:>10}\n", "", "initial", "final");
  fmt::print("{:<34} {:>10.4f} {:>10.4f}   (cube 0.806, sphere 1)\n",
             "sphericity pi^(1/3)(6V)^(2/3)/A", r.sphericity_initial, r.sphericity_final);
  fmt::print("{:<34} {:>10.4f} {:>10.4f}   (cube 0.577, sphere 1)\n",
             "axis / diagonal radius of phi=1/2", r.radius_ratio_initial, r.radius_ratio_final);
  fmt::print("mean radius {:.4f} (sphere of the cube's volume: {:.4f}); {} steps, t = {:.3f}\n",
             r.mean_radius_final, cube_sphere_radius(), r.run.steps,
             r.run.history.empty() ? 0.0 : r.run.history.back().time);
  return print_checks(cube_checks(r, c.cube_steps));
}

int print_table1(const VerifyCommand& c) {
  fmt::print("\n== Section 4.3, Table 1: sphere r = 0.25, epsilon = 0.0073*64/N, dt = h ==\n");
  fmt::print("stop ||phi^(n+1) - phi^n|| <= 1e-5; exact area pi/4 = {:.5f}, total mean "
             "curvature pi = {:.5f}\n",
             M_PI / 4, M_PI);
  const std::vector<Table1Reference>& paper = table1_reference();
  std::vector<SphereConvergenceRow> rows;
  for (const Table1Reference& ref : paper) {
    if (ref.n == 256 && !c.with_256) continue;
    if (c.quick && ref.n != 32) continue;
    Progress progress(c.quiet);
    rows.push_back(verify_sphere(ref.n, 1e-5, c.sphere_max_steps,
                                 [&](const StepRecord& s) { progress.step(s); }));
    progress.finish();
  }
  fmt::print("{:>5} {:>9} | {:>9} {:>9} {:>6} {:>6} | {:>9} {:>9} {:>6} {:>6} | {:>6} {:>8}\n",
             "N", "epsilon", "area", "paper", "rate", "paper", "H*A", "paper", "rate", "paper",
             "steps", "seconds");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    const Table1Reference& ref = paper[i];
    std::string ra = "", rt = "", pa = "", pt = "";
    if (i + 1 < rows.size()) {
      ra = fmt::format("{:.2f}", std::log2(std::abs(M_PI / 4 - r.area) /
                                           std::abs(M_PI / 4 - rows[i + 1].area)));
      rt = fmt::format("{:.2f}", std::log2(std::abs(M_PI - r.total_mean_curvature) /
                                           std::abs(M_PI - rows[i + 1].total_mean_curvature)));
    }
    if (i + 1 < paper.size()) {
      pa = fmt::format("{:.2f}", std::log2((M_PI / 4 - ref.area) / (M_PI / 4 - paper[i + 1].area)));
      pt = fmt::format("{:.2f}", std::log2((M_PI - ref.total_mean_curvature) /
                                           (M_PI - paper[i + 1].total_mean_curvature)));
    }
    fmt::print("{:>5} {:>9.6f} | {:>9.5f} {:>9.5f} {:>6} {:>6} | {:>9.5f} {:>9.5f} {:>6} {:>6} | "
               "{:>6} {:>8.1f}\n",
               r.n, r.epsilon, r.area, ref.area, ra, pa, r.total_mean_curvature,
               ref.total_mean_curvature, rt, pt, r.steps, r.wall_seconds);
  }
  fmt::print("relative difference to the paper: ");
  for (std::size_t i = 0; i < rows.size(); ++i)
    fmt::print("N={}: area {:+.2f}%, H*A {:+.2f}%  ", rows[i].n,
               100 * (rows[i].area / paper[i].area - 1),
               100 * (rows[i].total_mean_curvature / paper[i].total_mean_curvature - 1));
  fmt::print("\n");
  return print_checks(table1_checks(rows));
}

}  // namespace

CommandFn add_verify_command(CLI::App& root) {
  auto cmd = std::make_shared<VerifyCommand>();
  CLI::App* app = root.add_subcommand(
      "verify",
      "Reproduce the paper's verification (Section 4.1, Section 4.2 and Table 1) and check it: "
      "exit code 1 when a check fails");
  app->add_flag("--quick", cmd->quick,
                "Short mode for CI (about 10 s on one core): Section 4.1 at 32^3 with m = 8, "
                "Section 4.2 at 32^3, Table 1 at 32^3 only");
  app->add_flag("--with-256", cmd->with_256, "Also run Table 1 at 256^3 (long)");
  app->add_option("--only", cmd->only, "Run one experiment: transition, cube or table1")
      ->check(CLI::IsMember({"transition", "cube", "table1"}));
  CLI::Option* transition_grid =
      app->add_option("--transition-grid", cmd->transition_grid,
                      fmt::format("Grid of the Section 4.1 experiment, as run --grid takes (8 "
                                  "to {}; paper: h = 1/128; --quick: 32)",
                                  kMaxGrid))
          ->capture_default_str();
  CLI::Option* cube_grid =
      app->add_option("--cube-grid", cmd->cube_grid,
                      fmt::format("Grid of the Section 4.2 experiment, as run --grid takes (8 "
                                  "to {}; paper: 64; --quick: 32); epsilon stays the paper's 0.015",
                                  kMaxGrid))
          ->capture_default_str();
  app->add_option("--cube-steps", cmd->cube_steps, "Step limit of the Section 4.2 experiment")
      ->capture_default_str();
  add_threads_option(*app, cmd->threads);
  app->add_flag("--quiet", cmd->quiet, "No progress output");
  return {app, [cmd, transition_grid, cube_grid]() -> int {
            if (cmd->quick && cmd->with_256)
              throw UsageError("--with-256: not with --quick (which runs Table 1 at 32^3 only)");
            if (cmd->quick && transition_grid->count() == 0) cmd->transition_grid = 32;
            if (cmd->quick && cube_grid->count() == 0) cmd->cube_grid = 32;
            for (const auto& [name, n] : {std::pair<const char*, int>{"--transition-grid",
                                                                      cmd->transition_grid},
                                          {"--cube-grid", cmd->cube_grid}}) {
              const std::string problem = check_verify_grid(n);
              if (!problem.empty()) throw UsageError(fmt::format("{}: {}", name, problem));
            }
            if (cmd->cube_steps < 1)
              throw UsageError(
                  fmt::format("--cube-steps: got {}; accepted: >= 1", cmd->cube_steps));
            const int threads = apply_threads(cmd->threads);
            fmt::print("cmcsurf {} verify{} ({} threads)\n", version_string(),
                       cmd->quick ? " --quick" : "", threads);
            int failed = 0;
            if (cmd->only.empty() || cmd->only == "transition") failed += print_transition(*cmd);
            if (cmd->only.empty() || cmd->only == "cube") failed += print_cube(*cmd);
            if (cmd->only.empty() || cmd->only == "table1") failed += print_table1(*cmd);
            fmt::print("\nverify: {}\n", failed == 0 ? "all checks passed"
                                                     : fmt::format("{} check(s) FAILED", failed));
            std::fflush(stdout);
            return failed == 0 ? 0 : 1;
          }};
}

}  // namespace cmcsurf::cli
