// Periodic tetrahedral meshes of a solid: the mesh on the 3-torus (what a periodic mesher
// returns), its unfolding into a block of whole cells whose boundary nodes are paired with their
// images one period away, and the checks and quality measures of the result. See
// docs/volume_mesh.md.
#pragma once

#include <array>
#include <compare>
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "mesh/tri_mesh.h"

namespace cmcsurf {

// Tetrahedra on the unit 3-torus: corner c of tet t is vertices[tets[t][c]] + offsets[t][c]
// (whole periods). Positively oriented once the offsets are applied.
struct PeriodicTets {
  std::vector<Vec3> vertices;  // canonical positions in [0, 1)^3
  std::vector<std::array<std::int32_t, 4>> tets;
  std::vector<std::array<std::array<std::int8_t, 3>, 4>> offsets;
};

// A face of one tetrahedron of a torus mesh: its corners (vertex, whole periods) sorted and
// translated so that the first has offset 0, so that the two tets sharing a face give equal
// corners; `skip` is the tet's corner opposite the face.
struct TorusFace {
  std::array<std::pair<std::int32_t, std::array<int, 3>>, 3> corners;
  std::size_t tet = 0;
  int skip = 0;
};

// The faces that belong to one tetrahedron only: the boundary of the torus mesh (the solid's
// surface), sorted by corners.
std::vector<TorusFace> torus_boundary_faces(const PeriodicTets& t);

// An edge of a torus mesh: its vertex of smaller index u, the other w, and w's periods relative
// to u's; the same key in every tet that holds the edge.
struct TorusEdge {
  std::int32_t u = 0, w = 0;
  std::array<int, 3> rel{0, 0, 0};
  auto operator<=>(const TorusEdge&) const = default;
};

// The edge between the corners (a, periods oa) and (b, periods ob) of one tet.
inline TorusEdge torus_edge(std::int32_t a, const std::array<int, 3>& oa, std::int32_t b,
                            const std::array<int, 3>& ob) {
  if (b < a) return torus_edge(b, ob, a, oa);
  return {a, b, {ob[0] - oa[0], ob[1] - oa[1], ob[2] - oa[2]}};
}

// Node `slave` is node `master` moved by `translation` (output units): the pair a periodic
// boundary condition ties (u_slave = u_master + E translation).
struct PeriodicPair {
  std::int64_t slave = 0, master = 0;
  Vec3 translation{0, 0, 0};
};

// A tetrahedral mesh of tiles[0] x tiles[1] x tiles[2] cells, output units. Its outer boundary
// is the solid's surface plus the periodic cut: faces that come in pairs one block period apart,
// whose nodes are listed in `pairs`. A tetrahedron lies where its centroid falls in the box: a
// torus mesh split at the cell faces (mesh/periodic_cut.h) gives the box cut flat, any other a
// fundamental domain whose cut faces stay within about one element of the box faces.
struct TetMesh {
  std::vector<Vec3> nodes;
  std::vector<std::array<std::int64_t, 4>> tets;  // positively oriented
  std::vector<PeriodicPair> pairs;                // one per slave node
  Vec3 period{0, 0, 0};                           // the block's size along x, y, z
  // The torus mesh's boundary faces times the cells: the solid's surface in the block.
  std::size_t surface_faces = 0;
};

// Places each torus tet where its centroid lies in [0, 1)^3, copies it into every tile (at most
// 100 per axis) and merges the corners that coincide; scales by cell_size. Each image of a
// torus vertex that is not the first (the one nearest the block) becomes a slave of it.
TetMesh unfold_periodic_tets(const PeriodicTets& torus, const std::array<int, 3>& tiles,
                             double cell_size);

// Measures and checks of a TetMesh (FILE.json's "quality", "edge_length" and "checks":
// docs/volume_mesh.md). size_min, size_max: the edge bounds asked for (0: none), counted.
struct TetMeshStats {
  std::size_t nodes = 0, tets = 0, edges = 0;
  double volume = 0.0;
  std::size_t inverted = 0, degenerate = 0;  // signed volume < 0; |volume| < 1e-12 h^3
  std::size_t components = 0;           // in the block, joined through shared nodes
  std::size_t components_periodic = 0;  // the same with paired nodes joined
  std::size_t surface_faces = 0;             // the solid's boundary
  std::size_t periodic_faces = 0;            // the cut, matched in pairs one period apart
  std::size_t unmatched_faces = 0;           // boundary faces neither of the above
  std::size_t unpaired_nodes = 0;            // on a periodic face but in no pair
  // Nodes on a plane of the box (x = 0 or x = period_x, ...) whose image one period away along
  // that axis is not a node paired with them: a user tying the planes by coordinates finds no
  // partner for them (a node on two planes counts once per plane).
  std::size_t unpaired_plane_nodes = 0;
  double pair_mismatch = 0.0;  // max |x_slave - x_master - translation| / max period
  double min_dihedral_deg = 0.0, max_dihedral_deg = 0.0;
  double max_radius_edge = 0.0, mean_radius_edge = 0.0;  // circumradius / shortest edge
  std::array<std::size_t, 18> dihedral_histogram{};      // each tet's smallest angle, 10 deg
  double min_edge = 0.0, max_edge = 0.0, mean_edge = 0.0;
  std::size_t edges_below_min = 0, edges_above_max = 0;
  double size_min = 0.0, size_max = 0.0;  // the bounds asked for (0: none)
  // Of those below size_min: with both ends on the periodic cut, on the solid's surface.
  std::size_t edges_below_min_cut = 0, edges_below_min_surface = 0;
  // And with an end on an edge line of the box (two of its planes): where the surface or the
  // cut crosses a box edge, the node is forced there and its neighbour on a face may lie near.
  std::size_t edges_below_min_box_edge = 0;
  // The cut against the box [0, period]: nodes on each plane (x = 0, x = period_x, y = 0, ...),
  // periodic faces not on one plane, nodes outside the box, and periodic faces on a plane whose
  // image on the opposite plane (the same nodes one period away) is not a face there.
  std::array<std::size_t, 6> plane_nodes{};
  std::size_t periodic_faces_off_plane = 0;
  std::size_t nodes_outside_box = 0;
  std::size_t unmirrored_faces = 0;
};
TetMeshStats analyze_tet_mesh(const TetMesh& m, double size_min = 0.0, double size_max = 0.0);
nlohmann::json tet_mesh_stats_json(const TetMeshStats& s, const std::string& units);
// The non-empty 10-degree bins of a smallest-dihedral histogram: from_deg, to_deg, tets.
nlohmann::json dihedral_histogram_json(const std::array<std::size_t, 18>& histogram);

// Signed volume of the tet (a, b, c, d): positive when (b - a, c - a, d - a) is right-handed.
double tet_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

}  // namespace cmcsurf
