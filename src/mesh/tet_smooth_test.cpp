#include "mesh/tet_smooth.h"

#include <cmath>

#include <gtest/gtest.h>

#include "mesh/kuhn_torus_testing.h"
#include "mesh/periodic_cut.h"

namespace cmcsurf {
namespace {

TEST(TetSmooth, MinDihedralOfKnownTets) {
  // The Kuhn tet (0, e_x, e_x + e_y, 1): angles 45, 60 and 90 degrees; the regular tet:
  // acos(1/3); a flat one: -1.
  EXPECT_NEAR(tet_min_dihedral_deg({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {1, 1, 1}), 45.0, 1e-12);
  const double s = 1.0 / std::sqrt(2.0);
  EXPECT_NEAR(tet_min_dihedral_deg({1, 0, -s}, {-1, 0, -s}, {0, -1, s}, {0, 1, s}),
              std::acos(1.0 / 3.0) * 180.0 / M_PI, 1e-12);
  EXPECT_EQ(tet_min_dihedral_deg({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}), -1.0);
  EXPECT_EQ(tet_min_dihedral_deg({0, 0, 0}, {1, 0, 0}, {1, 1, 1}, {1, 1, 0}), -1.0);  // inverted
}

// The whole torus split at the cell faces, then smoothed towards a target above every tet's
// angle, so that every vertex is tried: the box stays filled and flat with mirrored faces.
TEST(TetSmooth, RaisesTheSmallestAngleAndKeepsTheFlatMirroredBox) {
  PeriodicTets t = kuhn_torus(4, 0.37, 0.15, 7);
  cut_at_cell_faces(t);
  std::vector<Vec3> before = t.vertices;
  const SliverSmoothing s = smooth_slivers(t, 60.0, 3);
  EXPECT_GT(s.moves, 0u);
  EXPECT_GT(s.min_dihedral_after, s.min_dihedral_before + 1.0);
  EXPECT_LE(s.tets_below_target_after, s.tets_below_target_before);
  EXPECT_EQ(s.fixed_vertices, 1u);  // no surface: the box's corner, on three faces
  // Moves within the cells: the volume is the torus's to round-off.
  EXPECT_NEAR(torus_volume(t), 1.0, 1e-12);
  std::size_t on_face = 0;
  for (std::size_t v = 0; v < t.vertices.size(); ++v)
    for (int a = 0; a < 3; ++a) {
      if (before[v][a] == 0.0) {
        ++on_face;
        ASSERT_EQ(t.vertices[v][a], 0.0);  // kept on its face, exactly
      }
      ASSERT_GT(t.vertices[v][a], -1e-300);
      ASSERT_LT(t.vertices[v][a], 1.0);
    }
  EXPECT_GT(on_face, 0u);
  const TetMeshStats m = analyze_tet_mesh(unfold_periodic_tets(t, {2, 1, 1}, 1.5));
  EXPECT_EQ(m.inverted, 0u);
  EXPECT_EQ(m.degenerate, 0u);
  EXPECT_NEAR(m.volume, 2 * 1.5 * 1.5 * 1.5, 1e-12 * 6.75);
  EXPECT_EQ(m.unmatched_faces, 0u);
  EXPECT_EQ(m.unpaired_nodes, 0u);
  EXPECT_EQ(m.periodic_faces_off_plane, 0u);
  EXPECT_EQ(m.nodes_outside_box, 0u);
  EXPECT_EQ(m.unmirrored_faces, 0u);
  EXPECT_EQ(m.pair_mismatch, 0.0);
  EXPECT_NEAR(m.min_dihedral_deg, s.min_dihedral_after, 1e-9);
}

// Half of the torus (a slab, whose two boundary planes are the solid's surface): the surface
// vertices stay where they are and so does the volume.
TEST(TetSmooth, KeepsTheSurfaceVertices) {
  PeriodicTets t = kuhn_torus_slab(6, 3);
  cut_at_cell_faces(t);
  const double volume = torus_volume(t);
  const TetMeshStats m0 = analyze_tet_mesh(unfold_periodic_tets(t, {1, 1, 1}, 1.0));
  const std::vector<Vec3> before = t.vertices;
  const SliverSmoothing s = smooth_slivers(t, 60.0, 3);
  EXPECT_GT(s.moves, 0u);
  EXPECT_GT(s.fixed_vertices, 0u);
  EXPECT_GE(s.min_dihedral_after, s.min_dihedral_before);
  EXPECT_GT(s.peeled, 0u);  // a target of 60 degrees peels many of the surface's tets
  EXPECT_NEAR(torus_volume(t), volume - s.peeled_volume, 1e-12);
  // The surface: every vertex that did not move is one of the fixed, and the fixed ones are
  // the slab's two boundary layers (no vertex on three faces here).
  std::size_t unmoved = 0;
  for (std::size_t v = 0; v < t.vertices.size(); ++v) unmoved += t.vertices[v] == before[v];
  EXPECT_GE(unmoved, s.fixed_vertices);
  const TetMeshStats m = analyze_tet_mesh(unfold_periodic_tets(t, {1, 1, 1}, 1.0));
  EXPECT_EQ(m.inverted, 0u);
  EXPECT_EQ(m.unmatched_faces, 0u);
  EXPECT_EQ(m.unmirrored_faces, 0u);
  EXPECT_EQ(m.nodes_outside_box, 0u);
  // The slab's jagged surface touches some faces from one side only (snapped vertices), so
  // opposite planes need not hold as many nodes; smoothing and peeling change no count.
  EXPECT_EQ(m.plane_nodes, m0.plane_nodes);
  EXPECT_EQ(m.periodic_faces, m0.periodic_faces);
}

// Without peeling (a part of a mesh, whose boundary is not all surface): the same moves, no
// tet removed, the volume kept to round-off.
TEST(TetSmooth, PeelsNothingWhenAskedNotTo) {
  PeriodicTets t = kuhn_torus_slab(6, 3);
  cut_at_cell_faces(t);
  PeriodicTets peeled = t;
  const std::size_t tets = t.tets.size();
  const double volume = torus_volume(t);
  const SliverSmoothing s = smooth_slivers(t, 60.0, 3, 0.0, 0.0, false);
  const SliverSmoothing with = smooth_slivers(peeled, 60.0, 3);
  EXPECT_EQ(s.peeled, 0u);
  EXPECT_GT(with.peeled, 0u);
  EXPECT_EQ(s.moves, with.moves);
  EXPECT_EQ(t.tets.size(), tets);
  EXPECT_NEAR(torus_volume(t), volume, 1e-12);
}

}  // namespace
}  // namespace cmcsurf
