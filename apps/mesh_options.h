// Options shared by `cmcsurf mesh`, `cmcsurf graded` and `run --mesh`: tiling, units, solid,
// format and output file; validation (UsageError) and writing the mesh with FILE.json.
#pragma once

#include <CLI/CLI.hpp>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "grid/field.h"
#include "mesh/scaffold.h"
#include "mesh/writers.h"

namespace cmcsurf::cli {

struct MeshOptionStrings {
  std::string tile = "1x1x1";
  double cell_size = 1.0;
  std::string units = "mm";
  std::string solid = "surface";
  bool other_phase = false;
  double thickness = 0.0;  // 0: not given
  std::string format;      // empty: from the extension of --out
  std::string out;
};
void add_mesh_output_options(CLI::App& app, MeshOptionStrings& s, bool with_sheet);

struct MeshPlan {
  ScaffoldParams params;
  MeshFormat format = MeshFormat::kStl;
  std::filesystem::path out;
};
// Checks every option against the field's grid n; throws UsageError naming the option.
MeshPlan finish_mesh_output_options(const MeshOptionStrings& s, int n);

// Reads phi from a run directory (DIR/field.vti) or a .vti file; UsageError naming
// `option` if the path does not exist.
Field load_phi(const std::string& from, const std::string& option);

// Writes the mesh, then FILE.json (the report plus `extra`), each atomically.
void write_mesh_with_report(const TriMesh& mesh, nlohmann::json report, const MeshPlan& plan,
                            const nlohmann::json& extra);

// "surface.<ext>" report for `run --mesh FORMAT`: the untiled surface in unit-cell units.
void write_run_surface_mesh(const std::filesystem::path& dir, const Field& phi,
                            const std::string& format);

}  // namespace cmcsurf::cli
