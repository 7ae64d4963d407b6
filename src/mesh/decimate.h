// Mesh-size control for printed parts (docs/scaffolds.md): quadric edge-collapse decimation by
// OpenMesh's decimater (Debian libopenmesh-dev), which refuses collapses that would break the
// manifold (link condition) and, with a tolerance, those that move the surface further than it
// (Hausdorff module). The flat caps on the box faces are kept. A result is accepted only while
// the solid stays closed, manifold, as many pieces, with its volume within a tolerance;
// otherwise the budget is relaxed (or the tolerance halved) and it retries.
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
  double error = 0.0;          // largest distance from the input's vertices to the result
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
