// cmcsurf sweep: placeholder until its issue lands.
#include <iostream>

#include "cli_common.h"
#include "commands.h"

namespace cmcsurf::cli {

CommandFn add_sweep_command(CLI::App& root) {
  CLI::App* app = root.add_subcommand("sweep", "Sweep volume fractions over surface families (not yet implemented)");
  app->group("");  // hidden from --help until implemented
  return {app, []() -> int {
            std::cerr << "error: cmcsurf sweep is not implemented yet\n";
            return kExitFailure;
          }};
}

}  // namespace cmcsurf::cli
