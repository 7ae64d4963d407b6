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

}  // namespace cmcsurf::cli
