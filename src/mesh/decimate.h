// Mesh-size control for printed parts (docs/scaffolds.md): edge-collapse decimation by
// meshoptimizer (Debian libmeshoptimizer-dev 0.18, meshopt_simplify: quadric error,
// topology-preserving collapses), accepted only while the solid stays closed, manifold, one
// piece, with its volume within a tolerance; otherwise the budget is relaxed and it retries.
#pragma once

#include <cstddef>

#include <nlohmann/json.hpp>

#include "mesh/tri_mesh.h"

namespace cmcsurf {

struct DecimateParams {
  std::size_t max_triangles = 0;  // 0: no triangle budget
  double tolerance = 0.0;         // chordal error bound in mesh units (0: none)
  double max_volume_change = 5e-3;  // relative
};

struct Decimated {
  TriMesh mesh;
  std::size_t triangles_before = 0, triangles_after = 0;
  double error = 0.0;          // meshoptimizer's error estimate achieved, mesh units
  double volume_change = 0.0;  // relative
  int attempts = 0;
  bool applied = false;        // false: no attempt passed the checks; mesh is the input
  bool within_budget = false;  // triangles_after <= max_triangles (or no budget)
  double seconds = 0.0;
};

// Components of the mesh by shared vertices (surface shells).
std::size_t mesh_shell_count(const TriMesh& m);

// Throws std::invalid_argument when neither a budget nor a tolerance is given.
Decimated decimate_solid(const TriMesh& m, const DecimateParams& p);

nlohmann::json decimated_json(const Decimated& d, const DecimateParams& p,
                              const std::string& units);

}  // namespace cmcsurf
