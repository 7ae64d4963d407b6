// Scaffolds from a periodic phase field: the phi = 1/2 surface, the network solid {phi > 1/2}
// (or its complement) and the sheet solid {|d| < T/2} around the surface, tiled and scaled to
// output units, with a report of the mesh's measures and checks. See docs/meshing.md.
#pragma once

#include <array>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "grid/field.h"
#include "mesh/tri_mesh.h"

namespace cmcsurf {

enum class SolidKind { kSurface, kNetwork, kSheet };
// "surface", "network", "sheet"; throws std::invalid_argument naming the accepted values.
SolidKind parse_solid_kind(const std::string& name);
const char* solid_kind_name(SolidKind k);

struct ScaffoldParams {
  std::array<int, 3> tiles{1, 1, 1};
  double cell_size = 1.0;    // output units per unit cell
  std::string units = "mm";
  SolidKind solid = SolidKind::kSurface;
  bool other_phase = false;  // phase 0 = {phi < 1/2} instead of phase 1
  double thickness = 0.0;    // sheet wall thickness, output units
  // Solids: keep the pieces the box cuts off the solid (default: removed, mesh/part.h).
  bool keep_fragments = false;
};

// Value at tiled cell (i, j, k), 0 <= i < tiles[0] * n etc. (cell centres (i + 1/2) h).
using TiledSampler = std::function<double(int i, int j, int k)>;

// Marching tetrahedra over the tiled cell centres, coordinates scaled by cell_size.
// solid = false: the open surface {f = iso} over nodes 0..tiles*n, i.e. exactly `tiles`
//   periods of the cell-centred lattice, spanning [h/2, tiles + h/2] * cell_size.
// solid = true: the closed boundary of {f > iso} within the box [0, tiles] * cell_size,
//   capped flat on the box faces (an outside pad layer beyond the box).
TriMesh mesh_tiled(const TiledSampler& f, int n, const std::array<int, 3>& tiles,
                   double cell_size, double iso, bool solid);

// The phi = iso surface of one unit cell on the 3-torus (TriMesh::period = 1), unit-cell
// coordinates: for the Euler characteristic V - E + F and the area per cell.
TriMesh periodic_surface_mesh(const Field& phi, double iso = 0.5);

// Signed distance from each cell centre to the periodic phi = iso surface mesh (unit-cell
// units, > 0 where phi > iso), exact to that mesh where |d| < band and clamped to +-band
// beyond. Closest triangles are seeded in the cubes the surface crosses and propagated by
// alternating sweeps over the 26 neighbours (periodic).
Field signed_distance(const Field& phi, double band, double iso = 0.5);

// The mesh in output units and its report (see docs/meshing.md for the keys). Solids are
// meshed as a PartLattice (mesh/part.h): fragments cut off by the box are removed unless
// keep_fragments, and the report's `topology` says how many, their volume, and whether the
// pore space percolates between opposite box faces.
struct Scaffold {
  TriMesh mesh;
  nlohmann::json report;
};
// phi: any ghost width. Throws std::invalid_argument on parameters out of range.
Scaffold build_scaffold(const Field& phi, const ScaffoldParams& p);

// The n x n values of z-plane k (0 <= k < n) of an n^3 field, x fastest; valid until the next
// call. Planes are asked for in the order the meshers below need them (each k at most twice).
using PlaneFn = std::function<const double*(int k)>;
// build_scaffold of a surface (p.solid == kSurface) from a field read plane by plane, for a
// field no process holds whole (a decomposed run's --mesh: pipeline/distributed_mesh.h). The
// same mesh and report as build_scaffold of the whole field.
Scaffold build_surface_scaffold(const PlaneFn& plane, int n, const ScaffoldParams& p);
// periodic_surface_mesh and periodic_surface_json of a field read plane by plane.
TriMesh periodic_surface_mesh(const PlaneFn& plane, int n, double iso = 0.5);
nlohmann::json periodic_surface_json(const PlaneFn& plane, int n);

// Mesh measures and checks in output units: counts, area, volume (solids), V - E + F (also per
// tile; the Euler characteristic only of a closed mesh), bounding box, edge and vertex checks.
nlohmann::json mesh_stats_json(const MeshStats& s, const std::array<int, 3>& tiles,
                               const std::string& units, bool solid);
// Topology and area of the periodic surface of one cell (unit-cell units).
nlohmann::json periodic_surface_json(const Field& phi);

}  // namespace cmcsurf
