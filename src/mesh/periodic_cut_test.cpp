#include "mesh/periodic_cut.h"

#include <cmath>

#include <gtest/gtest.h>

#include "mesh/kuhn_torus_testing.h"

namespace cmcsurf {
namespace {

// The whole torus split and unfolded must fill the box exactly, with a planar boundary whose
// opposite faces are mirror images, node for node.
void expect_flat_box(const TetMesh& mesh, const std::array<int, 3>& tiles, double L) {
  const TetMeshStats s = analyze_tet_mesh(mesh);
  expect_whole_torus_unfolded(s, tiles[0] * tiles[1] * tiles[2] * L * L * L);
  EXPECT_EQ(s.periodic_faces_off_plane, 0u);
  EXPECT_EQ(s.nodes_outside_box, 0u);
  EXPECT_EQ(s.unmirrored_faces, 0u);
  for (int a = 0; a < 3; ++a) {
    EXPECT_GT(s.plane_nodes[2 * a], 0u);
    EXPECT_EQ(s.plane_nodes[2 * a], s.plane_nodes[2 * a + 1]) << a;
  }
  // Every node on a max plane is the slave of the node on the min plane one period away.
  for (const auto& p : mesh.pairs)
    for (int a = 0; a < 3; ++a) {
      const double k = p.translation[a] / mesh.period[a];
      ASSERT_TRUE(k == 0.0 || k == 1.0) << k;
      if (k == 1.0) {
        ASSERT_EQ(mesh.nodes[p.slave][a], mesh.period[a]);
      }
    }
}

TEST(PeriodicCut, SplitTorusUnfoldsIntoTheBoxWithMirroredFaces) {
  // Vertices off the planes (0.37), on them (0), and near them (0.02 of a cube: snapped), each
  // on a regular and a jittered lattice (all split cases: 1-3, 2-2 and with vertices on the
  // plane).
  for (double shift : {0.37, 0.0, 0.02})
    for (double jitter : {0.0, 0.15}) {
      SCOPED_TRACE(::testing::Message() << "shift " << shift << " jitter " << jitter);
      PeriodicTets torus = kuhn_torus(4, shift, jitter, 7);
      const std::size_t before = torus.tets.size();
      const CellFaceCut cut = cut_at_cell_faces(torus);
      EXPECT_EQ(cut.degenerate, 0u);
      if (shift == 0.02) {
        EXPECT_GT(cut.snapped, 0u);
      }
      if (shift == 0.37 && jitter == 0.0) {  // 0.37 cubes from the faces, beyond snap 0.3
        EXPECT_EQ(cut.snapped, 0u);
        EXPECT_GT(cut.split_tets, 0u);
      }
      EXPECT_GE(torus.tets.size(), before);
      for (const std::array<int, 3> tiles : {std::array<int, 3>{1, 1, 1}, {2, 1, 3}})
        expect_flat_box(unfold_periodic_tets(torus, tiles, 2.5), tiles, 2.5);
    }
}

TEST(PeriodicCut, NoSnapStillConformsAndTheBoxChecksSeeAJaggedCutAndAMovedNode) {
  PeriodicTets torus = kuhn_torus(3, 0.37, 0.15, 11);
  // Unsplit: a fundamental domain, whose cut faces leave the planes.
  const TetMeshStats jagged = analyze_tet_mesh(unfold_periodic_tets(torus, {1, 1, 1}, 1.0));
  EXPECT_GT(jagged.periodic_faces_off_plane, 0u);
  EXPECT_GT(jagged.nodes_outside_box, 0u);
  const CellFaceCut cut = cut_at_cell_faces(torus, 0.0);
  EXPECT_EQ(cut.snapped, 0u);
  const TetMesh flat = unfold_periodic_tets(torus, {1, 1, 1}, 1.0);
  expect_flat_box(flat, {1, 1, 1}, 1.0);
  // A node on x = 1 moved within its plane: its faces lose their mirror images on x = 0.
  TetMesh moved = flat;
  for (const auto& p : moved.pairs)
    if (p.translation[0] == 1.0 && p.translation[1] == 0.0 && p.translation[2] == 0.0) {
      moved.nodes[p.slave][1] += 1e-9;
      break;
    }
  EXPECT_GT(analyze_tet_mesh(moved).unmirrored_faces, 0u);
}

}  // namespace
}  // namespace cmcsurf
