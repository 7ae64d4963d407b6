// cmcsurf mesh: placeholder until its issue lands.
#include <iostream>

#include "cli_common.h"
#include "commands.h"

namespace cmcsurf::cli {

CommandFn add_mesh_command(CLI::App& root) {
  CLI::App* app = root.add_subcommand("mesh", "Mesh a computed field (not yet implemented)");
  app->group("");  // hidden from --help until implemented
  return {app, []() -> int {
            std::cerr << "error: cmcsurf mesh is not implemented yet\n";
            return kExitFailure;
          }};
}

}  // namespace cmcsurf::cli
