#include "mesh/tet_mesh.h"

#include <cmath>

#include <gtest/gtest.h>

#include "mesh/kuhn_torus_testing.h"

namespace cmcsurf {
namespace {

TEST(TetMesh, UnfoldedKuhnTorusFillsTheBlockWithEveryCutNodePaired) {
  const int m = 3;
  for (const std::array<int, 3> tiles : {std::array<int, 3>{1, 1, 1}, {2, 1, 3}}) {
    const double L = 2.5;
    const TetMesh mesh = unfold_periodic_tets(kuhn_torus(m), tiles, L);
    const TetMeshStats s = analyze_tet_mesh(mesh, 0.9 * L / m, 1.01 * std::sqrt(3.0) * L / m);
    const int cells = tiles[0] * tiles[1] * tiles[2];
    EXPECT_EQ(s.tets, std::size_t(6 * m * m * m * cells));
    // The tets tile a fundamental domain: its volume is the block's, to round-off.
    expect_whole_torus_unfolded(s, cells * L * L * L);
    // No solid surface: the whole boundary is the periodic cut, matched face for face.
    EXPECT_EQ(s.surface_faces, 0u);
    EXPECT_EQ(s.components_periodic, 1u);
    // Paired nodes are one point of the torus: the block's m^3 * cells vertices remain.
    EXPECT_EQ(s.nodes - mesh.pairs.size(), std::size_t(m * m * m * cells));
    // Kuhn tets: dihedral angles 45, 60 and 90 degrees; circumradius (the cube's, sqrt(3)/2
    // of the edge h) over the shortest edge h.
    EXPECT_NEAR(s.min_dihedral_deg, 45.0, 1e-9);
    EXPECT_NEAR(s.max_dihedral_deg, 90.0, 1e-9);
    EXPECT_NEAR(s.max_radius_edge, std::sqrt(3.0) / 2, 1e-12);
    EXPECT_NEAR(s.min_edge, L / m, 1e-12);
    EXPECT_NEAR(s.max_edge, std::sqrt(3.0) * L / m, 1e-12);
    EXPECT_EQ(s.edges_below_min, 0u);
    EXPECT_EQ(s.edges_above_max, 0u);
    for (const auto& p : mesh.pairs)
      for (int a = 0; a < 3; ++a) {
        const double k = p.translation[a] / mesh.period[a];
        ASSERT_NEAR(k, std::round(k), 1e-15);  // whole block periods
      }
  }
}

TEST(TetMesh, ChecksSeeAHoleAnInvertedTetAndABrokenPair) {
  const PeriodicTets torus = kuhn_torus(3);
  // A tet removed on the torus: its four faces become the solid's surface, nothing unmatched.
  PeriodicTets holed = torus;
  holed.tets.erase(holed.tets.begin() + 7);
  holed.offsets.erase(holed.offsets.begin() + 7);
  const TetMeshStats h = analyze_tet_mesh(unfold_periodic_tets(holed, {1, 1, 1}, 1.0));
  EXPECT_EQ(h.surface_faces, 4u);
  EXPECT_EQ(h.unmatched_faces, 0u);
  // Corners swapped: one tet inverted.
  TetMesh mesh = unfold_periodic_tets(torus, {1, 1, 1}, 1.0);
  TetMesh flipped = mesh;
  std::swap(flipped.tets[0][0], flipped.tets[0][1]);
  EXPECT_EQ(analyze_tet_mesh(flipped).inverted, 1u);
  // A pair dropped: its slave's faces no longer match their twins; a pair moved: mismatch.
  TetMesh dropped = mesh;
  dropped.pairs.pop_back();
  const TetMeshStats d = analyze_tet_mesh(dropped);
  EXPECT_GT(d.unmatched_faces, 0u);
  TetMesh moved = mesh;
  moved.nodes[moved.pairs[0].slave][0] += 1e-9;
  EXPECT_NEAR(analyze_tet_mesh(moved).pair_mismatch, 1e-9, 1e-15);
}

}  // namespace
}  // namespace cmcsurf
