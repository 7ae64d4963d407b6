#include "mesh/tet_sizing.h"

#include <cmath>

#include <gtest/gtest.h>

#include "mesh/kuhn_torus_testing.h"
#include "mesh/periodic_cut.h"

namespace cmcsurf {
namespace {

// The flat box's checks of an unfolding: mirrored planar faces, every plane node paired.
void expect_flat_box(const TetMeshStats& m) {
  EXPECT_EQ(m.inverted, 0u);
  EXPECT_EQ(m.degenerate, 0u);
  EXPECT_EQ(m.unmatched_faces, 0u);
  EXPECT_EQ(m.unpaired_nodes, 0u);
  EXPECT_EQ(m.periodic_faces_off_plane, 0u);
  EXPECT_EQ(m.nodes_outside_box, 0u);
  EXPECT_EQ(m.unmirrored_faces, 0u);
  EXPECT_EQ(m.pair_mismatch, 0.0);
}

// The whole torus cut without snapping, so that the split leaves pieces with short edges near
// the faces: collapsing them fills the same box, flat and mirrored, with no edge below.
TEST(TetSizing, CollapsesShortEdgesAndKeepsTheFlatMirroredBox) {
  PeriodicTets t = kuhn_torus(4, 0.37, 0.15, 7);
  cut_at_cell_faces(t, 0.0);
  const double lo = 0.04;  // the cube is 0.25: a sixth of it
  const std::vector<Vec3> before = t.vertices;
  const EdgeSizing s = enforce_edge_sizes(t, {lo, 0.0, 0.0});
  EXPECT_GT(s.below_min_before, 20u);
  EXPECT_GT(s.collapsed, 0u);
  EXPECT_EQ(s.below_min_after, count_edges_outside(t, lo, 0.0).first);
  // Left: edges joining vertices on different faces of the box (neither may leave its face)
  // and collapses that would drop a tet under the floor; measured 47 of 250.
  EXPECT_LE(s.below_min_after, s.below_min_before / 4);
  // No surface: every collapse moves a vertex within the box's cells, the volume is the
  // torus's to round-off.
  EXPECT_NEAR(torus_volume(t), 1.0, 1e-12);
  const TetMeshStats m = analyze_tet_mesh(unfold_periodic_tets(t, {2, 1, 1}, 1.5), lo * 1.5);
  expect_flat_box(m);
  EXPECT_NEAR(m.volume, 2 * 1.5 * 1.5 * 1.5, 1e-12 * 6.75);
  EXPECT_EQ(m.unpaired_plane_nodes, 0u);
  // The cell's, in both tiles (and twice over on the planes the tiles' images share).
  EXPECT_GE(m.edges_below_min, 2 * s.below_min_after);
}

// Edges longer than the size are split at their midpoints: none is left, the box the same.
TEST(TetSizing, SplitsLongEdgesAndKeepsTheFlatMirroredBox) {
  PeriodicTets t = kuhn_torus(3, 0.37, 0.1, 5);
  cut_at_cell_faces(t);
  const double hi = 0.45;  // cube 1/3: its face diagonals 0.47, body diagonal 0.58
  const EdgeSizing s = enforce_edge_sizes(t, {0.0, hi, 0.0});
  EXPECT_GT(s.above_max_before, 50u);
  EXPECT_GT(s.split, 0u);
  EXPECT_EQ(s.above_max_after, count_edges_outside(t, 0.0, hi).second);
  EXPECT_LE(s.above_max_after, s.above_max_before / 10);
  EXPECT_NEAR(torus_volume(t), 1.0, 1e-12);
  const TetMeshStats m = analyze_tet_mesh(unfold_periodic_tets(t, {1, 2, 1}, 1.0), 0.0, hi);
  expect_flat_box(m);
  EXPECT_NEAR(m.volume, 2.0, 1e-12 * 2.0);
  EXPECT_GE(m.edges_above_max, 2 * s.above_max_after);
}

// On a slab, a surface vertex collapses only along the surface and only where the new
// surface passes within the facet distance of it: with distance 0, only within the jagged
// surface's flat patches, so the volume stays the same to round-off.
TEST(TetSizing, SurfaceCollapsesKeepTheSurfaceWithinTheFacetDistance) {
  PeriodicTets t = kuhn_torus_slab(6, 3);
  cut_at_cell_faces(t, 0.0);
  const double volume = torus_volume(t);
  const TetMeshStats m0 = analyze_tet_mesh(unfold_periodic_tets(t, {1, 1, 1}, 1.0));
  const EdgeSizing s = enforce_edge_sizes(t, {0.03, 0.0, 0.0});
  EXPECT_GT(s.collapsed, 0u);
  EXPECT_NEAR(torus_volume(t), volume, 1e-12);
  const TetMeshStats m = analyze_tet_mesh(unfold_periodic_tets(t, {1, 1, 1}, 1.0));
  EXPECT_EQ(m.inverted, 0u);
  EXPECT_EQ(m.unmatched_faces, 0u);
  EXPECT_EQ(m.unmirrored_faces, 0u);
  EXPECT_EQ(m.nodes_outside_box, 0u);
  EXPECT_EQ(m.components_periodic, m0.components_periodic);
  EXPECT_EQ(m.surface_faces, m0.surface_faces);  // interior collapses leave the surface
  // With a facet distance, more go, and the volume moves by at most that times the area.
  PeriodicTets u = kuhn_torus_slab(6, 3);
  cut_at_cell_faces(u, 0.0);
  const EdgeSizing su = enforce_edge_sizes(u, {0.03, 0.0, 0.01});
  EXPECT_GT(su.collapsed, s.collapsed);
  EXPECT_LT(analyze_tet_mesh(unfold_periodic_tets(u, {1, 1, 1}, 1.0)).surface_faces,
            m0.surface_faces);
  EXPECT_LT(std::abs(torus_volume(u) - volume), 0.01 * 2 * 1.5);  // two jagged planes
}

// The slab's jagged surface touches some cell faces at a single snapped vertex, from one side:
// a node on one plane without a partner on the other. Lifted off the face (split first where
// the vertex pinches the solid diagonally), and the vertices on a box edge whose tets fill an
// L of the cells around it moved into the L's middle cell and re-cut, every plane node is
// paired and opposite planes hold as many nodes.
TEST(TetSizing, OneSidedFaceVerticesAreLiftedSoTheirPlaneNodesArePaired) {
  PeriodicTets t = kuhn_torus_slab(6, 3);
  cut_at_cell_faces(t);
  const double volume = torus_volume(t);
  const TetMeshStats m0 = analyze_tet_mesh(unfold_periodic_tets(t, {1, 1, 1}, 1.0));
  EXPECT_GT(m0.unpaired_plane_nodes, 0u);  // the check can fail
  const OneSidedFaceVertices s = lift_one_sided_face_vertices(t, 1e-3);
  EXPECT_GT(s.found, 0u);
  EXPECT_EQ(s.lifted, s.found);
  EXPECT_LE(s.max_lift, 1e-3);
  EXPECT_GT(s.moved_into_cell, 0u);  // measured: 18 L vertices on x = z = 0 and y = z = 0
  EXPECT_EQ(s.left, 0u);
  // A lift moves a surface vertex by <= 1e-3, an L move by <= sqrt(2) max_cell_move, each
  // within tets of total volume < 1 resp. a surface star of area < 0.1 (six triangles of legs
  // <= 1/6, the slab's lattice): measured 0.0029. Its move is at most the snap's share of
  // its shortest edge, itself at most a lattice edge, (1 + 2 jitter) / 6.
  EXPECT_LE(s.max_cell_move, kDefaultCellFaceSnap * 1.3 / 6);
  EXPECT_LT(std::abs(torus_volume(t) - volume),
            1e-3 * double(s.lifted) +
                std::sqrt(2.0) * s.max_cell_move * 0.1 * double(s.moved_into_cell));
  const TetMeshStats m = analyze_tet_mesh(unfold_periodic_tets(t, {1, 1, 1}, 1.0));
  expect_flat_box(m);
  // No tet below the floor the moves keep: min(kSizingFloorDeg, the smallest before).
  EXPECT_GE(m.min_dihedral_deg, std::min(kSizingFloorDeg, m0.min_dihedral_deg) - 1e-9);
  for (const std::array<int, 3> tiles : {std::array<int, 3>{1, 1, 1}, {2, 1, 3}}) {
    const TetMeshStats mt = analyze_tet_mesh(unfold_periodic_tets(t, tiles, 1.0));
    expect_flat_box(mt);
    EXPECT_EQ(mt.unpaired_plane_nodes, 0u);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(mt.plane_nodes[2 * a], mt.plane_nodes[2 * a + 1]) << a;
  }
}

}  // namespace
}  // namespace cmcsurf
