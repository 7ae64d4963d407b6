// Sliver removal on a periodic tetrahedral mesh after the flat cut (mesh/periodic_cut.h): the
// vertices of tets with small dihedral angles are moved to raise the smallest angle of their
// tets (max-min smoothing). Done on the torus, where a vertex on a cell face is one vertex for
// both faces of the box, so a move applies to its mirror image identically. See
// docs/volume_mesh.md.
#pragma once

#include <array>
#include <cstddef>

#include "mesh/tet_mesh.h"

namespace cmcsurf {

// The smallest dihedral angle that is sought, degrees, and the sweeps over the vertices of the
// tets below it. 15 / 6: measured on the 64^3 gyroid sheet and network (docs/volume_mesh.md),
// more sweeps gain under 0.1 degree.
inline constexpr double kSliverTargetDeg = 15.0;
inline constexpr int kSliverSweeps = 6;

struct SliverSmoothing {
  double min_dihedral_before = 0.0, min_dihedral_after = 0.0;  // degrees
  std::size_t tets_below_target_before = 0, tets_below_target_after = 0;
  std::size_t vertices_tried = 0;  // summed over the sweeps
  std::size_t moves = 0;           // accepted moves
  int sweeps = 0;                  // run (stops early when a sweep moves nothing)
  std::size_t fixed_vertices = 0;  // on the solid's surface or on three cell faces
  std::size_t peeled = 0;          // surface slivers removed
  double peeled_volume = 0.0;      // their volume, unit cells
  // Each torus tet's smallest angle in 10-degree bins (TetMeshStats' histogram, per cell).
  std::array<std::size_t, 18> histogram_before{}, histogram_after{};
};

// Moves vertices of tets whose smallest dihedral angle is below target_deg. Never moved: a
// vertex of the solid's surface (the torus mesh's boundary faces), so the surface, its facet
// distance and the volume stay as meshed. A vertex on a cell face (a coordinate exactly 0)
// keeps that coordinate, moving within the face, and no vertex leaves [0, 1) along another
// axis, so no tet crosses a face. A move is kept only when the smallest angle of the vertex's
// tets grows and none turns inverted; deterministic (vertices in index order). Then tets still
// below the target with two or three faces on the surface and none on a cell face are removed
// where the surface stays manifold and every corner's node in the box stays in use (their
// volume is reported).
// max_edge (unit cells; 0: no limit): a move may not make an edge of the vertex longer than
// this or than its longest edge before the move; min_edge likewise shorter than this or than
// its shortest edge before. peel false: no tet is removed (a part of a mesh whose boundary is
// not all surface, such as one vertex's star).
SliverSmoothing smooth_slivers(PeriodicTets& t, double target_deg = kSliverTargetDeg,
                               int sweeps = kSliverSweeps, double max_edge = 0.0,
                               double min_edge = 0.0, bool peel = true);

// The smallest of the six dihedral angles of the tet, degrees; -1 for a tet of volume
// <= 1e-12 of its longest edge cubed or negative.
double tet_min_dihedral_deg(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

}  // namespace cmcsurf
