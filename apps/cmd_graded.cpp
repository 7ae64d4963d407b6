// cmcsurf graded: placeholder until its issue lands.
#include <iostream>

#include "cli_common.h"
#include "commands.h"

namespace cmcsurf::cli {

CommandFn add_graded_command(CLI::App& root) {
  CLI::App* app = root.add_subcommand("graded", "Graded-porosity scaffold (not yet implemented)");
  app->group("");  // hidden from --help until implemented
  return {app, []() -> int {
            std::cerr << "error: cmcsurf graded is not implemented yet\n";
            return kExitFailure;
          }};
}

}  // namespace cmcsurf::cli
