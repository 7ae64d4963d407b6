// Options shared by `cmcsurf mesh`, `cmcsurf graded` and `run --mesh`: tiling, units, solid,
// format and output file; validation (UsageError) and writing the mesh with FILE.json.
#pragma once

#include <CLI/CLI.hpp>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "grid/field.h"
#include "io/mesh_output.h"

namespace cmcsurf::cli {

// The options as strings, checked by plan_mesh_output (io/mesh_output.h).
using MeshOptionStrings = MeshOutputOptions;
void add_mesh_output_options(CLI::App& app, MeshOptionStrings& s, bool with_sheet);

// Checks every option against the field's grid n (plan_mesh_output); throws UsageError naming
// the option.
MeshPlan finish_mesh_output_options(const MeshOptionStrings& s, int n);

// Reads phi from a run directory (DIR/field.vti, or DIR/field.pvti with its pieces after a
// decomposed run: io/pvti.h) or a .vti or .pvti file; UsageError naming `option` if the path
// does not exist or a folder holds neither field file (or both).
Field load_phi(const std::string& from, const std::string& option);

// write_mesh_with_report, write_run_surface_mesh: io/mesh_output.h.

}  // namespace cmcsurf::cli
