// Each subcommand registers its options and returns the function that runs it.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <utility>

namespace cmcsurf::cli {

using CommandFn = std::pair<CLI::App*, std::function<int()>>;

CommandFn add_run_command(CLI::App& root);
CommandFn add_verify_command(CLI::App& root);
CommandFn add_surfaces_command(CLI::App& root);
CommandFn add_sweep_command(CLI::App& root);   // apps/cmd_sweep.cpp
CommandFn add_merge_command(CLI::App& root);   // apps/cmd_merge.cpp
CommandFn add_mesh_command(CLI::App& root);    // apps/cmd_mesh.cpp
CommandFn add_graded_command(CLI::App& root);  // apps/cmd_graded.cpp
CommandFn add_report_command(CLI::App& root);  // apps/cmd_report.cpp
CommandFn add_scaffold_command(CLI::App& root);  // apps/cmd_scaffold.cpp
CommandFn add_properties_command(CLI::App& root);  // apps/cmd_properties.cpp
CommandFn add_scattering_command(CLI::App& root);  // apps/cmd_scattering.cpp
CommandFn add_volume_mesh_command(CLI::App& root);  // apps/cmd_volume_mesh.cpp
CommandFn add_schema_command(CLI::App& root);  // apps/cmd_schema.cpp (hidden)

}  // namespace cmcsurf::cli
