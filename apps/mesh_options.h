// Options shared by `cmcsurf mesh`, `cmcsurf graded` and `run --mesh`: tiling, units, solid,
// format and output file; validation (UsageError) and writing the mesh with FILE.json.
#pragma once

#include <CLI/CLI.hpp>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "grid/field.h"
#include "io/file_identity.h"
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
// metadata: the field file's cmcsurf header values (surface, ...), when given.
Field load_phi(const std::string& from, const std::string& option,
               std::map<std::string, std::string>* metadata = nullptr);

// The files `from` (a run folder or a field file) stands for, labelled with `option`: the
// field file (a .pvti's pieces too) and the run's report.json beside it.
std::vector<FileRole> field_inputs(const std::string& from, const std::string& option);
// The run report beside the field `from` stands for (DIR/report.json; for DIR/field.vti or
// DIR/field.pvti too), or an empty path.
std::filesystem::path field_run_report(const std::string& from);
// Refuses (UsageError) an `out` or its FILE.json that is the same file as one of `reads`.
void refuse_overwriting_inputs(const std::vector<FileRole>& reads,
                               const std::filesystem::path& out);
// Refuses (TopologyChangeError, exit 1) a member whose report says its topology is not its
// family's, unless `accept` (--accept-topology-change).
void check_field_topology(const std::string& from, bool accept);

// write_mesh_with_report, write_run_surface_mesh: io/mesh_output.h.

}  // namespace cmcsurf::cli
