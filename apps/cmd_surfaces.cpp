// cmcsurf surfaces: the built-in initial surfaces.
#include <fmt/format.h>

#include "cli_common.h"
#include "commands.h"
#include "surfaces/initial.h"

namespace cmcsurf::cli {

CommandFn add_surfaces_command(CLI::App& root) {
  CLI::App* app = root.add_subcommand("surfaces", "List the built-in surfaces and their formulas");
  return {app, []() -> int {
            fmt::print("{:<10} {:<6} {:<9} {}\n", "name", "nodal", "balanced", "description");
            for (const SurfaceInfo& s : builtin_surfaces())
              fmt::print("{:<10} {:<6} {:<9} {}\n", s.name, s.nodal ? "yes" : "no",
                         s.nodal ? (s.balanced ? "yes" : "no") : "-", s.description);
            fmt::print(
                "\nexpr:<formula>  a user nodal function of x, y, z in [0, 2 pi) over the cell "
                "(muParser syntax), phase 1 where it is > 0.\nbalanced: the two sides of the "
                "nodal surface are congruent, so the alpha = 0.5 member is a candidate minimal "
                "surface; for an unbalanced one it is not.\n");
            return 0;
          }};
}

}  // namespace cmcsurf::cli
