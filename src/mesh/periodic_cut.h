// Flat cell faces for a periodic tetrahedral mesh: the torus mesh is split along the planes
// x = 0, y = 0, z = 0 (mod 1) so that no tet crosses a face of the unit cell. Unfolded
// (mesh/tet_mesh.h), the block's boundary is then planar, and its opposite faces carry one and
// the same triangulation, since on the torus they are the same faces. See docs/volume_mesh.md.
#pragma once

#include <array>
#include <cstddef>

#include "mesh/tet_mesh.h"
#include "mesh/tet_sizing.h"

namespace cmcsurf {

// A vertex nearer a cell face than this share of its shortest edge is moved onto the face (or
// away from it to that distance) before the split, so that the split makes no piece thinner
// than that. 0.3: on a 64^3 gyroid the fewest tets under 10 degrees (0.2: 4x as many; 0.45:
// moves that would flatten a tet, refused, leave slivers), the volume moved by 0.03 %.
inline constexpr double kDefaultCellFaceSnap = 0.3;

struct CellFaceCut {
  std::size_t snapped = 0;          // vertices moved onto a cell face
  std::size_t pushed = 0;           // moved away from it instead (onto would flatten a tet)
  std::size_t snaps_refused = 0;    // both would have flattened a tet (kept in place)
  double max_snap = 0.0;            // the longest move, unit cells
  std::size_t split_tets = 0;       // tets a face crossed (summed over the three axes)
  std::size_t cut_vertices = 0;     // vertices added where an edge crosses a face
  std::size_t degenerate = 0;       // pieces of zero volume (a check: none expected)
};

// Snaps (snap: share of the shortest incident edge; 0: none) and splits `t` in place. The split
// of a tet into tets is conforming: a quadrilateral is cut along the diagonal from its vertex
// of smallest index, the same choice in both tets that share it (the prism rule of Dompierre
// et al. 1999, which always yields three tets); a vertex added on an edge is shared by every
// tet holding that edge. Tets stay positively oriented.
CellFaceCut cut_at_cell_faces(PeriodicTets& t, double snap = kDefaultCellFaceSnap);

// A vertex on a cell face whose tets all lie on one side of it (where the solid's surface
// touches the face at a vertex the snap put there) has one image in the box: a node on one
// plane with no partner on the opposite one. Each is moved off the face into its tets' side by
// min(kOneSidedLift of its shortest edge, max_lift), halved while an incident tet would lose
// over half its volume or an edge of it would leave [min_edge, max_edge] (0: no bound) having
// been inside. A vertex on two or three faces whose tets lie in cells that meet only along a
// line or at a point (diagonally: it pinches the solid) is first split into one vertex per
// group of cells joined across faces, each then lifted so.
inline constexpr double kOneSidedLift = 0.05;
struct OneSidedFaceVertices {
  std::size_t found = 0;   // vertex-face incidences (a vertex on two faces counts twice)
  std::size_t lifted = 0;  // moved off the face
  std::size_t split = 0;   // copies made of pinching vertices (diagonal cells)
  double max_lift = 0.0;   // unit cells
  // On a box edge or corner with tets on both sides of each face but not in every cell
  // around it (an L around an edge; 7 of 8 cells at a corner): moved off faces, into the cell
  // joined across faces to the most others or else off fewer faces to where its tets fill
  // every cell around it, by up to kDefaultCellFaceSnap of its shortest edge (the snap's
  // reach: a move of the lift's size leaves pieces as thin as it, under 1 degree), and the
  // tets in the other cells re-cut at those faces; kept only if no changed tet falls below
  // min(floor_deg, the smallest dihedral angle of the mesh before).
  std::size_t moved_into_cell = 0;
  std::size_t recut_tets = 0;   // tets split by those re-cuts
  double max_cell_move = 0.0;   // the largest distance off a face, unit cells
  // Of those, moved by the second pass (PairingMove below): a changed tet under the floor.
  std::size_t moved_below_floor = 0;
  double min_dihedral_below_floor = 180.0;  // their smallest angle, degrees
  // Left on a face with tets in some of the cells around them but not all: an L vertex whose
  // move would flatten a tet or leave one below the quality floor, or a refused lift. Some of
  // their images in the box lack a partner.
  std::size_t left = 0;
};
// PairingMove: where no move of an L or corner vertex keeps its changed tets above the floor
// (a corner vertex's pieces are tents of its height off a face over its neighbours' triangles
// on that face, so their angle grows with the move: measured 3.9 deg at the snap's reach),
// the moves are tried again up to half its shortest edge, the free vertices of its tets and
// of its neighbours' tets smoothed, and the best kept if no changed tet is under
// kPairingFloorDeg: a node without a partner breaks every periodic condition a user ties by
// planes, a 5-degree tet does not (the default meshes' smallest angle is 6.3-6.5 deg).
inline constexpr double kPairingFloorDeg = 5.0;
inline constexpr std::array<double, 6> kPairingMoveShares{0.5, 0.4, 0.3, 0.2, 0.15, 0.1};

OneSidedFaceVertices lift_one_sided_face_vertices(PeriodicTets& t, double max_lift,
                                                  double min_edge = 0.0, double max_edge = 0.0,
                                                  double floor_deg = kSizingFloorDeg);

}  // namespace cmcsurf
