// The welded periodic surface mesh (mesh/periodic_surface.h) as one JSON file that keeps what
// OBJ or STL cannot: each triangle's wrap offsets. Written by `cmcsurf mesh --periodic`; the
// keys are listed in docs/science.md ("The welded periodic mesh"). Writes only.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

#include "mesh/periodic_surface.h"

namespace cmcsurf {

// Its measures and checks: vertices, edges, triangles, V - E + F (the surface's Euler
// characteristic), area, closed, manifold.
nlohmann::json periodic_mesh_stats_json(const PeriodicSurfaceMesh& m);

// format, cell, the arrays (vertices, triangles, offsets, normals, mean_curvature,
// gaussian_curvature), stats, and `extra`'s keys; compact (one line), atomically.
void write_periodic_mesh_json(const std::filesystem::path& path, const PeriodicSurfaceMesh& m,
                              const nlohmann::json& extra = {});

}  // namespace cmcsurf
