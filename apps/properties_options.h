// The --properties stage options of run and sweep (docs/properties.md): declared here once for
// both commands, with the output options a resume restores. The stage itself is the library's
// (pipeline/properties_stage.h).
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "pipeline/properties_stage.h"
#include "run_control.h"

namespace cmcsurf::cli {

// --properties, --properties-solid, --properties-porosity, --properties-thickness,
// --properties-nodal, --properties-grid-check; `what` names the solid's owner in the help
// ("the run's", "each member's").
struct PropertiesOptions {
  PropertiesStage stage;
  std::string porosity;  // --properties-porosity as typed: P or P1,P2,... (a ramp)
};
void add_properties_options(CLI::App& app, PropertiesOptions& options, const std::string& what);

// After parsing: any --properties-* option turns the stage on; a bad combination or range is
// a UsageError naming the option. `surface`, `grid`: the run's (a sweep's first member's
// surface will do: the checks do not depend on it).
void finish_properties_options(PropertiesOptions& options, const std::string& surface, int grid);

// The stage's options among a checkpoint's or sweep.json's "outputs" (unset ones left out), and
// back for a resume (options given on the command line win).
void add_properties_outputs(nlohmann::json& outputs, const PropertiesOptions& options);
void restore_properties_outputs(const OutputRestorer& r, PropertiesOptions& options);

}  // namespace cmcsurf::cli
