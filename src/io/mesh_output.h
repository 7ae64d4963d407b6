// A scaffold mesh from a user's options: tiling, units, solid, thickness, format and output
// file, checked with the messages of `cmcsurf mesh` (OptionError naming the option), and the
// mesh written with its FILE.json report. Shared by apps/ (mesh, graded, run --mesh) and
// python/ (cmcsurf.mesh, Mesh.save).
#pragma once

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "grid/field.h"
#include "mesh/scaffold.h"
#include "mesh/writers.h"

namespace cmcsurf {

// The options as a user gives them (the command line's strings).
struct MeshOutputOptions {
  std::string tile = "1x1x1";  // AxBxC or A
  double cell_size = 1.0;
  std::string units = "mm";
  std::string solid = "surface";
  bool other_phase = false;
  bool keep_fragments = false;
  // Mesh a member whose topology differs from its family's (pipeline/member_topology.h).
  bool accept_topology_change = false;
  double thickness = 0.0;  // 0: not given
  std::string format;      // empty: from the extension of out
  std::string out;
};

// The range of --cell-size (and of scaffold's --size), in output units: below it float32 and
// 3MF coordinates (6 decimals) lose the lattice; pick a smaller unit instead.
inline constexpr double kMinCellSize = 1e-3, kMaxCellSize = 1e6;

struct MeshPlan {
  ScaffoldParams params;
  MeshFormat format = MeshFormat::kStl;
  std::filesystem::path out;
  MeshMetadata meta;  // 3MF only
};

// The scaffold options (tile, cell_size, units, solid, other_phase, thickness) checked against
// the field's grid n; throws OptionError naming the option.
ScaffoldParams scaffold_params(const MeshOutputOptions& s, int n);
// The format: `format`, or from the extension of `out` when empty; and `out` must not be a
// directory. Throws OptionError naming --format or --out.
MeshFormat mesh_output_format(const std::string& format, const std::filesystem::path& out);
// Both of the above.
MeshPlan plan_mesh_output(const MeshOutputOptions& s, int n);

// Writes the mesh, then FILE.json (the report plus file, format, file_bytes, write_seconds,
// version and `extra`), each atomically.
void write_mesh_with_report(const TriMesh& mesh, nlohmann::json report, const MeshPlan& plan,
                            const nlohmann::json& extra);

// "surface.<ext>" report for `run --mesh FORMAT`: the untiled surface in unit-cell units.
void write_run_surface_mesh(const std::filesystem::path& dir, const Field& phi,
                            const std::string& format);
// The same for a scaffold built before (build_scaffold with default ScaffoldParams, or a
// decomposed run's pipeline/distributed_mesh.h).
void write_run_surface_mesh(const std::filesystem::path& dir, const Scaffold& s,
                            const std::string& format);

}  // namespace cmcsurf
