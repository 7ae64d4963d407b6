// cmcsurf: triply periodic constant-mean-curvature surfaces by a Cahn-Hilliard phase field.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <vector>

#include "cahn_hilliard/time_step.h"
#include "cli_common.h"
#include "commands.h"
#include "parallel/decomposition.h"
#include "model/option_checks.h"

namespace {

// Runs the command line; under mpirun every process parses the same arguments and validates
// them identically, so bad input ends every process with the same exit code.
int run_main(int argc, char** argv) {
  using namespace cmcsurf::cli;
  CLI::App app{
      "cmcsurf: triply periodic constant-mean-curvature surfaces (Schwarz P, D, Schoen G and "
      "relatives) at a prescribed volume fraction, by a Cahn-Hilliard phase field solved with "
      "nonlinear FAS multigrid.\nExample: cmcsurf run --surface G --volume-fraction 0.3 --grid 64 "
      "--out gyroid30"};
  app.set_version_flag("--version", version_string());
  app.require_subcommand(1);
  std::vector<CommandFn> commands = {add_run_command(app),      add_sweep_command(app),
                                     add_mesh_command(app),     add_graded_command(app),
                                     add_verify_command(app),   add_surfaces_command(app),
                                     add_report_command(app),   add_scaffold_command(app),
                                     add_properties_command(app), add_scattering_command(app),
                                     add_volume_mesh_command(app), add_schema_command(app),
                                     add_merge_command(app)};
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return kExitUsage;
  }
  // OpenMP starts OMP_NUM_THREADS threads at the first parallel region, whatever --threads.
  if (const std::string why = cmcsurf::check_omp_num_threads(std::getenv("OMP_NUM_THREADS"));
      !why.empty()) {
    std::cerr << "error: OMP_NUM_THREADS: " << why << "\n";
    return kExitUsage;
  }
  const auto world = cmcsurf::Decomposition::world();
  for (auto& [sub, fn] : commands) {
    if (!sub->parsed()) continue;
    try {
      if (world->distributed() && sub->get_name() != "run" && sub->get_name() != "sweep")
        throw UsageError(fmt::format(
            "`cmcsurf {}` runs on one process; only `cmcsurf run` (decomposed over the ranks) "
            "and `cmcsurf sweep` (members side by side in groups of ranks) run under mpirun "
            "(started with {} ranks): run it without mpirun",
            sub->get_name(), world->ranks()));
      return fn();
    } catch (const UsageError& e) {
      std::cerr << "error: " << e.what() << "\n";
      return kExitUsage;
    } catch (const cmcsurf::SolverDiverged& e) {
      std::cerr << "error: the run diverged and was stopped; nothing was written.\n"
                << e.what() << "\n";
      return kExitFailure;
    } catch (const std::exception& e) {
      std::cerr << "error: " << e.what() << "\n";
      // Other processes may wait in a collective for this one: end them all.
      if (world->distributed()) world->abort_all(kExitFailure);
      return kExitFailure;
    }
  }
  return kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  cmcsurf::ParallelSession session(&argc, &argv);
  const auto world = cmcsurf::Decomposition::world();
  // Only rank 0 talks and writes.
  if (world->rank() != 0) {
    if (!std::freopen("/dev/null", "w", stdout) || !std::freopen("/dev/null", "w", stderr))
      world->abort_all(cmcsurf::cli::kExitFailure);
  }
  int code = run_main(argc, argv);
  // Every process ends with the worst exit code (rank 0 alone may have failed to write).
  code = world->max_exit_code(code);
  std::fflush(stdout);
  return code;
}
