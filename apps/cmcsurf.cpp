// cmcsurf: triply periodic constant-mean-curvature surfaces by a Cahn-Hilliard phase field.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <iostream>
#include <vector>

#include "cahn_hilliard/time_step.h"
#include "cli_common.h"
#include "commands.h"

int main(int argc, char** argv) {
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
                                     add_verify_command(app),   add_surfaces_command(app)};
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
  for (auto& [sub, fn] : commands) {
    if (!sub->parsed()) continue;
    try {
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
      return kExitFailure;
    }
  }
  return kExitUsage;
}
