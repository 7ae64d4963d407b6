// The priority-queue collapser (decimate_solid) against OpenMesh's decimater
// (decimate_solid_ref) on the same parts, and on its own on a sphere.
#include "mesh/edge_collapse.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <map>

#include "mesh/decimate.h"
#include "mesh/scaffold_part.h"
#include "surfaces/initial.h"

namespace cmcsurf {
namespace {

// A G network and a G sheet, 1 x 1 x 1 cells of the nodal gyroid at 16^3, undecimated.
TriMesh gyroid_part(SolidKind solid) {
  InitialFieldParams ip;
  ip.surface = "G";
  ScaffoldDesign d;
  d.solid = solid;
  d.cell_size = 1.0;
  d.size = {1.0, 1.0, 1.0};
  d.morphometry = false;
  return design_scaffold(make_initial_field(ip, 16, 2), d).mesh;
}

void expect_same_solid(const TriMesh& in, const Decimated& dm) {
  const MeshStats s = analyze_mesh(dm.mesh);
  EXPECT_TRUE(s.closed());
  EXPECT_TRUE(s.manifold());
  EXPECT_EQ(s.degenerate_triangles, 0u);
  EXPECT_EQ(s.duplicate_triangles, 0u);
  EXPECT_EQ(mesh_shell_count(dm.mesh), mesh_shell_count(in));
  EXPECT_LE(std::abs(s.volume / mesh_volume(in) - 1.0), 5e-3);
}

// To a quarter of the triangles the collapser keeps the solid closed, manifold and in as many
// pieces within 0.5 % of its volume, reaches the budget wherever OpenMesh does (on the sheet
// OpenMesh's checks failed and it relaxed the budget to 5670 of 3780; the collapser met it at
// the same error, 0.036), and its error is at most twice OpenMesh's (measured 0.0068 against
// 0.0043 on the network: OpenMesh's area-weighted quadrics and its order of equal costs).
TEST(EdgeCollapse, BudgetMatchesTheReference) {
  for (const SolidKind solid : {SolidKind::kNetwork, SolidKind::kSheet}) {
    const TriMesh in = gyroid_part(solid);
    DecimateParams p;
    p.max_triangles = in.triangles.size() / 4;
    const Decimated fast = decimate_solid(in, p);
    const Decimated ref = decimate_solid_ref(in, p);
    ASSERT_TRUE(fast.applied);
    ASSERT_TRUE(ref.applied);
    EXPECT_TRUE(fast.within_budget);
    expect_same_solid(in, fast);
    EXPECT_GT(fast.error, 0.0);
    EXPECT_LE(fast.triangles_after, ref.triangles_after);
    EXPECT_LE(fast.error, 2.0 * ref.error) << "reference " << ref.error;
  }
}

// A user's part must not depend on OMP_NUM_THREADS: the G network built and decimated with 1
// and with 2 threads gives the same input and the same output, vertex for vertex.
TEST(EdgeCollapse, SameResultForAnyThreadCount) {
  const int before = omp_get_max_threads();
  TriMesh in[2];
  Decimated out[2];
  for (int k = 0; k < 2; ++k) {
    omp_set_num_threads(k + 1);
    in[k] = gyroid_part(SolidKind::kNetwork);
    DecimateParams p;
    p.max_triangles = in[k].triangles.size() / 4;
    out[k] = decimate_solid(in[k], p);
  }
  omp_set_num_threads(before);
  EXPECT_EQ(in[0].vertices, in[1].vertices);
  EXPECT_EQ(in[0].triangles, in[1].triangles);
  EXPECT_EQ(out[0].triangles_after, out[1].triangles_after);
  EXPECT_EQ(out[0].error, out[1].error);
  EXPECT_EQ(out[0].mesh.vertices, out[1].mesh.vertices);
  EXPECT_EQ(out[0].mesh.triangles, out[1].mesh.triangles);
}

// With a chordal tolerance the surface stays within it, measured independently both ways
// (symmetric_distance, sampled at the input's mean edge; the true Hausdorff distance is at
// most the reported bound), and the collapser keeps at most 1.25 times the triangles OpenMesh
// keeps for the same tolerance (measured 2788 against 2482 on the network, 9090 against 7970
// on the sheet, 1.12 and 1.14). 0.01 cells is 16 % of the 16^3 lattice's spacing, as 0.01 mm,
// the command's default, is of 2 mm cells at --grid 32.
TEST(EdgeCollapse, ToleranceHoldsOnTheSurface) {
  for (const SolidKind solid : {SolidKind::kNetwork, SolidKind::kSheet}) {
    const TriMesh in = gyroid_part(solid);
    DecimateParams p;
    p.tolerance = 0.01;
    const Decimated fast = decimate_solid(in, p);
    const Decimated ref = decimate_solid_ref(in, p);
    ASSERT_TRUE(fast.applied);
    expect_same_solid(in, fast);
    const SymmetricDistance e = symmetric_distance(in, fast.mesh);
    EXPECT_LE(std::max(e.a_to_b, e.b_to_a), p.tolerance);
    EXPECT_DOUBLE_EQ(std::max(e.a_to_b, e.b_to_a), fast.error);
    EXPECT_LT(fast.triangles_after, 0.65 * in.triangles.size());
    EXPECT_LE(fast.triangles_after, 1.25 * ref.triangles_after)
        << "reference " << ref.triangles_after;
  }
}

// An octahedron subdivided four times onto the unit sphere (2048 triangles): collapsed to 100
// triangles it stays one closed manifold shell of genus 0 and locked vertices do not move.
TEST(EdgeCollapse, SphereStaysAClosedShell) {
  TriMesh m;
  m.vertices = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  m.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                 {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (int level = 0; level < 4; ++level) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      if (auto it = mid.find(key); it != mid.end()) return it->second;
      Vec3 p{};
      for (int c = 0; c < 3; ++c) p[c] = 0.5 * (m.vertices[a][c] + m.vertices[b][c]);
      const double len = std::sqrt(dot(p, p));
      for (double& x : p) x /= len;
      m.vertices.push_back(p);
      return mid[key] = std::uint32_t(m.vertices.size() - 1);
    };
    std::vector<std::array<std::uint32_t, 3>> next;
    for (const auto& t : m.triangles) {
      const std::uint32_t a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]),
                          c = midpoint(t[2], t[0]);
      next.insert(next.end(), {{t[0], a, c}, {t[1], b, a}, {t[2], c, b}, {a, b, c}});
    }
    m.triangles = next;
  }
  ASSERT_EQ(m.triangles.size(), 2048u);
  std::vector<std::uint8_t> locked(m.vertices.size(), 0);
  locked[0] = locked[4] = 1;
  CollapseParams p;
  p.target_triangles = 100;
  const TriMesh r = collapse_edges(m, locked, p);
  const MeshStats s = analyze_mesh(r);
  EXPECT_LE(r.triangles.size(), 100u);
  EXPECT_TRUE(s.closed());
  EXPECT_TRUE(s.manifold());
  EXPECT_EQ(s.euler, 2);
  EXPECT_EQ(s.degenerate_triangles, 0u);
  int kept = 0;
  for (const Vec3& v : r.vertices) kept += v == m.vertices[0] || v == m.vertices[4];
  EXPECT_EQ(kept, 2);
  // 100 triangles inscribed in the unit sphere hold most of its volume.
  EXPECT_GT(s.volume, 0.9 * 4.0 / 3.0 * M_PI);
}

// The optimised collapser against the frozen reference on the same inputs and budget. Serial,
// it makes the same collapses in the same order: the same mesh. In 4 slabs (the seams then
// collapsed by the serial pass) it reaches the budget, keeps the solid closed, manifold, in as
// many pieces and within 0.5 % of its volume, and its sampled distance to the input stays
// within 2.5 times the reference's. Measured (network, sheet): 0.0146, 0.0363 against 0.0071,
// 0.0361; on a part this small the seams, frozen in the first pass, hold a large share of the
// triangles and the free rest is collapsed further to meet the budget.
TEST(EdgeCollapse, MatchesTheReferenceOnQuality) {
  for (const SolidKind solid : {SolidKind::kNetwork, SolidKind::kSheet}) {
    const TriMesh in = gyroid_part(solid);
    CollapseParams p;
    p.target_triangles = in.triangles.size() / 4;
    const TriMesh ref = collapse_edges_ref(in, {}, p);
    const SymmetricDistance dr = symmetric_distance(in, ref);
    const double ref_error = std::max(dr.a_to_b, dr.b_to_a);
    for (const int slabs : {1, 4}) {
      p.slabs = slabs;
      const TriMesh out = collapse_edges(in, {}, p);
      if (slabs == 1) {
        EXPECT_EQ(out.vertices, ref.vertices);
        EXPECT_EQ(out.triangles, ref.triangles);
      }
      const MeshStats s = analyze_mesh(out);
      EXPECT_EQ(out.triangles.size(), ref.triangles.size()) << "slabs " << slabs;
      EXPECT_TRUE(s.closed());
      EXPECT_TRUE(s.manifold());
      EXPECT_EQ(s.degenerate_triangles, 0u);
      EXPECT_EQ(mesh_shell_count(out), mesh_shell_count(in));
      EXPECT_LE(std::abs(s.volume / mesh_volume(in) - 1.0), 5e-3);
      const SymmetricDistance d = symmetric_distance(in, out);
      const double error = std::max(d.a_to_b, d.b_to_a);
      EXPECT_LE(error, 2.5 * ref_error) << "slabs " << slabs << ", reference " << ref_error;
      std::printf("%s, %d slab(s): error %.4g, reference %.4g\n",
                  solid == SolidKind::kSheet ? "sheet" : "network", slabs, error, ref_error);
    }
  }
}

// With an error bound and no budget, the slabs stop where the serial collapser stops: within
// 3 % of its triangles, and the same result for 1 and 2 threads (the slabs are set by the
// input, not by the threads).
TEST(EdgeCollapse, SlabsStopAtTheBoundAndRepeat) {
  const TriMesh in = gyroid_part(SolidKind::kSheet);
  CollapseParams p;
  p.max_error = 0.0025;
  p.slabs = 1;
  const TriMesh serial = collapse_edges(in, {}, p);
  p.slabs = 4;
  const int before = omp_get_max_threads();
  TriMesh out[2];
  for (int k = 0; k < 2; ++k) {
    omp_set_num_threads(k + 1);
    out[k] = collapse_edges(in, {}, p);
  }
  omp_set_num_threads(before);
  EXPECT_EQ(out[0].vertices, out[1].vertices);
  EXPECT_EQ(out[0].triangles, out[1].triangles);
  EXPECT_LT(serial.triangles.size(), 0.7 * in.triangles.size());
  EXPECT_NEAR(double(out[0].triangles.size()) / serial.triangles.size(), 1.0, 0.03);
  const MeshStats s = analyze_mesh(out[0]);
  EXPECT_TRUE(s.closed());
  EXPECT_TRUE(s.manifold());
  EXPECT_EQ(mesh_shell_count(out[0]), mesh_shell_count(in));
}

}  // namespace
}  // namespace cmcsurf
