#include <gtest/gtest.h>

#include <cmath>

#include "mesh/decimate.h"
#include "mesh/morphometry.h"
#include "mesh/part.h"
#include "mesh/scaffold_part.h"
#include "mesh/shape.h"
#include "mesh/writers.h"
#include "measure/sharp_volume.h"
#include "support/temp_dir.h"
#include "surfaces/initial.h"

namespace cmcsurf {
namespace {

// The nodal surface F + 1/2 (Eqs. 7-9): its 1/2 level is {F = 0}, volume fraction 1/2.
Field nodal(const std::string& surface, int n) {
  InitialFieldParams ip;
  ip.surface = surface;
  return make_initial_field(ip, n, 2);
}

Field from_function(int n, const std::function<double(double, double, double)>& f) {
  Field g(n, 1);
  for_each_cell(
      n, [&](int i, int j, int k) { g(i, j, k) = f((i + 0.5) / n, (j + 0.5) / n, (k + 0.5) / n); });
  g.exchange_halo();
  return g;
}

void expect_clean_solid(const TriMesh& m) {
  const MeshStats s = analyze_mesh(m);
  EXPECT_TRUE(s.closed());
  EXPECT_TRUE(s.manifold());
  EXPECT_EQ(s.degenerate_triangles, 0u);
  EXPECT_EQ(s.duplicate_triangles, 0u);
  EXPECT_GT(s.volume, 0.0);
}

// On a whole number of cells the part's lattice is the tiled one: the same values at the same
// places (the trilinear weights snap to the cell centres).
TEST(Part, WholeCellsSampleTheCellValues) {
  const Field phi = nodal("G", 16);
  const PartLattice lat = sample_part(phi, {2.0, 1.0, 1.0}, 1.0, [](double v) { return v; });
  ASSERT_EQ(lat.nodes, (std::array<int, 3>{32, 16, 16}));
  for (int k = 0; k < 16; k += 5)
    for (int i = 0; i < 32; i += 3)
      EXPECT_FLOAT_EQ(lat.a[lat.index(i, 2, k)], float(phi(i % 16, 2, k)));
}

// A box that cuts the P network at 1.75 cells leaves six loose pieces at its edges: they are
// found, measured by their own meshes (their volumes add up to the difference the removal
// makes), removed, and the rest is one closed manifold piece; --keep-fragments keeps them.
TEST(Part, FragmentsCutByTheBoxAreRemovedAndMeasured) {
  const Field phi = nodal("P", 32);
  auto network = [](double v) { return v - 0.5; };
  PartLattice lat = sample_part(phi, {1.75, 1.75, 1.75}, 1.0, network);
  const PartTopology kept = clean_part(lat, 0.0, true);
  const double v_kept = mesh_volume(mesh_part(lat, 0.0));
  ASSERT_EQ(kept.fragments, 6u);
  EXPECT_FALSE(kept.fragments_removed);
  const PartTopology t = clean_part(lat, 0.0, false);
  EXPECT_TRUE(t.fragments_removed);
  EXPECT_EQ(t.fragments, kept.fragments);
  EXPECT_EQ(t.solid_components, t.fragments + 1);
  const TriMesh m = mesh_part(lat, 0.0);
  expect_clean_solid(m);
  EXPECT_EQ(mesh_shell_count(m), 1u);
  EXPECT_NEAR(v_kept - mesh_volume(m), t.fragment_volume, 1e-9);
  EXPECT_GT(t.fragment_volume, 0.0);
  EXPECT_TRUE(t.percolates());
  EXPECT_EQ(t.closed_pores, 0u);
  // The removed nodes are gone: the cleaned solid is one component.
  for (std::size_t id = 0; id < lat.count(); ++id)
    if (lat.removed[id]) lat.a[id] = -1.0f;
  EXPECT_EQ(clean_part(lat, 0.0, false).solid_components, 1u);
}

// Spherical pores of radius 0.3 cells in a solid: closed cells, found as such (no axis
// percolates, one closed pore per cell) and refused by design_scaffold.
TEST(Part, ClosedCellsDoNotPercolate) {
  const Field g = from_function(16, [](double x, double y, double z) {
    return std::hypot(x - 0.5, y - 0.5, z - 0.5) - 0.3;  // solid outside the ball
  });
  PartLattice lat = sample_part(g, {2.0, 2.0, 1.0}, 1.0, [](double v) { return v; });
  const PartTopology t = clean_part(lat, 0.0, false);
  EXPECT_FALSE(t.pore_percolates[0] || t.pore_percolates[1] || t.pore_percolates[2]);
  EXPECT_EQ(t.closed_pores, 4u);
  EXPECT_EQ(t.solid_components, 1u);
  ScaffoldDesign d;  // the same balls as pores of a network member phi = 1/2 + g
  d.size = {2.0, 2.0, 1.0};
  d.cell_size = 1.0;
  Field phi = g;
  for_each_cell(16, [&](int i, int j, int k) { phi(i, j, k) = 0.5 + g(i, j, k); });
  phi.exchange_halo();
  d.porosity = 0.1131;  // the balls' 4/3 pi 0.3^3
  EXPECT_THROW(design_scaffold(phi, d), ClosedCellError);
}

// Porosity targets: a sheet's thickness is solved to 1e-4, a network keeps the member's level
// on whole cells (porosity = 1 - volume fraction within 1e-3) and is shifted when a trimmed
// box moves it further; both are one closed piece whose pores percolate.
TEST(Part, PorosityHitsTheTargetForSheetAndNetwork) {
  for (const std::string surface : {"G", "P"}) {
    const Field phi = nodal(surface, 32);
    for (const Vec3 size : {Vec3{2.0, 2.0, 2.0}, Vec3{1.7, 2.0, 2.3}}) {
      ScaffoldDesign d;
      d.cell_size = 1.0;
      d.size = size;
      d.solid = SolidKind::kSheet;
      d.porosity = 0.7;
      d.morphometry = false;
      const ScaffoldPart sheet = design_scaffold(phi, d);
      EXPECT_NEAR(sheet.report["porosity"].get<double>(), 0.7, 1e-4) << surface << size[0];
      expect_clean_solid(sheet.mesh);
      EXPECT_EQ(mesh_shell_count(sheet.mesh), 1u);
      EXPECT_GT(sheet.report["sheet"]["thickness"].get<double>(), 0.0);
      d.solid = SolidKind::kNetwork;
      d.porosity = 0.5;
      const ScaffoldPart net = design_scaffold(phi, d);
      EXPECT_NEAR(net.report["porosity"].get<double>(), 0.5, 1e-3) << surface << size[0];
      expect_clean_solid(net.mesh);
      EXPECT_EQ(mesh_shell_count(net.mesh), 1u);
      EXPECT_EQ(net.report["topology"]["closed_pores"].get<int>(), 0);
      if (size[0] == 2.0) {
        EXPECT_EQ(net.report["solve"]["level"].get<double>(), 0.0);
      }
    }
  }
}

// A graded network (porosity 0.58 -> 0.42 along z over three cells) from three members
// G + 1/2 + c (porosities 0.60, 0.50, 0.40): one closed manifold piece whose pores percolate,
// the porosity of each cell along z within 0.03 of the ramp's value there and decreasing.
// Without the members' morphometry (a 72^3 local thickness of both phases each, nine tenths of
// this test's time under the sanitizers): cli.scaffold_mesh_size checks it on a graded part.
TEST(Part, GradedPorosityFollowsTheRamp) {
  std::vector<GradedMember> members(3);
  const double offsets[3] = {-0.3, 0.0, 0.3};
  for (int m = 0; m < 3; ++m) {
    members[m].phi = nodal("G", 24);
    for_each_cell(24, [&](int i, int j, int k) { members[m].phi(i, j, k) += offsets[m]; });
    members[m].phi.exchange_halo();
    members[m].volume_fraction = sharp_volume_fraction(members[m].phi);
  }
  ScaffoldDesign d;
  d.cell_size = 1.0;
  d.size = {1.0, 1.0, 3.0};
  d.morphometry = false;
  PorosityRamp ramp;
  ramp.from = 0.58;
  ramp.to = 0.42;
  const ScaffoldPart part = design_graded_scaffold(members, d, ramp);
  expect_clean_solid(part.mesh);
  EXPECT_EQ(mesh_shell_count(part.mesh), 1u);
  const nlohmann::json& profile = part.report["graded"]["profile"];
  ASSERT_EQ(profile.size(), 3u);
  for (std::size_t b = 0; b < profile.size(); ++b) {
    EXPECT_NEAR(profile[b]["porosity_nodes"].get<double>(),
                profile[b]["porosity_target"].get<double>(), 0.03);
    if (b > 0) {
      EXPECT_LT(profile[b]["porosity_nodes"].get<double>(),
                profile[b - 1]["porosity_nodes"].get<double>());
    }
  }
  EXPECT_NEAR(part.report["porosity"].get<double>(), 0.5, 0.01);
  EXPECT_FALSE(part.report["morphometry"].contains("members"));
  ramp.from = 0.95;  // beyond the members
  EXPECT_THROW(design_graded_scaffold(members, d, ramp), std::invalid_argument);
}

// A graded sheet (porosity 0.8 -> 0.6 along z over three cells) around the nodal G surface at
// 24^3: one closed manifold piece, the mean porosity to the sheet's 1e-4, each cell's node
// porosity within 0.01 of the ramp there (measured 1e-3 on the CMC G at 32^3) and decreasing,
// the wall thicker at the dense end, the end cells measured.
TEST(Part, GradedSheetFollowsTheRamp) {
  ScaffoldDesign d;
  d.solid = SolidKind::kSheet;
  d.cell_size = 1.0;
  d.size = {1.0, 1.0, 3.0};
  PorosityRamp ramp;
  ramp.from = 0.8;
  ramp.to = 0.6;
  const ScaffoldPart part = design_graded_sheet(nodal("G", 24), d, ramp);
  expect_clean_solid(part.mesh);
  EXPECT_EQ(mesh_shell_count(part.mesh), 1u);
  EXPECT_NEAR(part.report["porosity"].get<double>(), 0.7, 1e-4);
  const nlohmann::json& profile = part.report["graded"]["profile"];
  ASSERT_EQ(profile.size(), 3u);
  for (std::size_t b = 0; b < profile.size(); ++b) {
    EXPECT_NEAR(profile[b]["porosity_nodes"].get<double>(),
                profile[b]["porosity_target"].get<double>(), 0.01);
    if (b > 0) {
      EXPECT_LT(profile[b]["porosity_nodes"].get<double>(),
                profile[b - 1]["porosity_nodes"].get<double>());
    }
  }
  const nlohmann::json& sheet = part.report["sheet"];
  EXPECT_LT(sheet["thickness_from"].get<double>(), sheet["thickness"].get<double>());
  EXPECT_LT(sheet["thickness"].get<double>(), sheet["thickness_to"].get<double>());
  ASSERT_EQ(part.report["morphometry"]["members"].size(), 2u);
  EXPECT_LT(part.report["morphometry"]["members"][0]["wall_thickness"]["mean"].get<double>(),
            part.report["morphometry"]["members"][1]["wall_thickness"]["mean"].get<double>());
  d.solid = SolidKind::kNetwork;
  EXPECT_THROW(design_graded_sheet(nodal("G", 24), d, ramp), std::invalid_argument);
}

// A box as a closed outward mesh (12 triangles).
TriMesh box_mesh(const Vec3& lo, const Vec3& hi) {
  TriMesh m;
  for (int c = 0; c < 8; ++c)
    m.vertices.push_back({c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2]});
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}

// --shape: a G network filling a 2 x 2 x 1.5 cell block placed off the lattice's origin is one
// closed manifold piece inside the block, with the porosity over the block's volume within
// 1e-3 of the target; a dense skin adds solid and the porosity still holds (the level moves).
// The shape comes through the STL reader (binary written by write_stl).
TEST(Part, ShapeFillHoldsThePorosityOverTheShape) {
  TempDir dir("part_test");
  write_stl(dir / "block.stl", box_mesh({0.3, 0.2, 0.1}, {2.3, 2.2, 1.6}));
  ShapeFill shape;
  shape.mesh = read_stl(dir / "block.stl");
  ASSERT_EQ(shape.mesh.triangles.size(), 12u);
  ASSERT_EQ(shape.mesh.vertices.size(), 8u);
  ScaffoldDesign d;
  d.cell_size = 1.0;
  d.porosity = 0.6;
  d.morphometry = false;
  const Field phi = nodal("G", 24);
  for (const double skin : {0.0, 0.08}) {
    shape.skin = skin;
    const ScaffoldPart part = design_scaffold(phi, d, &shape);
    expect_clean_solid(part.mesh);
    const nlohmann::json& t = part.report["topology"];
    EXPECT_EQ(t["solid_components"].get<int>() - t["fragments"].get<int>(), 1);
    // Without a skin the pores open onto the surface (one shell); a skin closes them in (a
    // warning), each closed pore an inner shell of the one piece.
    if (skin == 0.0) {
      EXPECT_EQ(mesh_shell_count(part.mesh), 1u);
    } else {
      EXPECT_GT(t["closed_pores"].get<int>(), 0);
      EXPECT_EQ(mesh_shell_count(part.mesh), 1u + t["closed_pores"].get<std::size_t>());
    }
    EXPECT_NEAR(part.report["shape"]["volume"].get<double>(), 6.0, 1e-6);
    EXPECT_NEAR(part.report["porosity"].get<double>(), 0.6, 1e-3) << skin;
    const MeshStats s = analyze_mesh(part.mesh);
    for (int c = 0; c < 3; ++c) {
      EXPECT_GE(s.min[c], shape.mesh.vertices[0][c] - 0.01);
      EXPECT_LE(s.max[c], shape.mesh.vertices[7][c] + 0.01);
    }
  }
}

// A sheet graded by depth in a 3 x 3 x 3 cell block (nodal G at 16^3): porosity 0.5 at the
// surface to 0.7 at one cell deep and below. One closed manifold piece whose porosity is the
// ramp's mean over the block's nodes (a sheet's 1e-4, with the cut); the outer band and the
// core within 0.03 of their targets (16^3 walls are 1.5-2.5 voxels; measured 0.008 at 32^3 in
// cli.scaffold_graded_fill), the core more porous; the wall thicker at the surface. A ramp by
// depth without a shape, or of no depth, is refused.
TEST(Part, GradedSheetByDepthInAShape) {
  ShapeFill shape;
  shape.mesh = box_mesh({0, 0, 0}, {3, 3, 3});
  ScaffoldDesign d;
  d.solid = SolidKind::kSheet;
  d.cell_size = 1.0;
  d.morphometry = false;
  PorosityRamp ramp;
  ramp.from = 0.5;
  ramp.to = 0.7;
  ramp.by_surface = true;
  ramp.depth = 1.0;
  const Field phi = nodal("G", 16);
  const ScaffoldPart part = design_graded_sheet(phi, d, ramp, {}, &shape);
  expect_clean_solid(part.mesh);
  const nlohmann::json& g = part.report["graded"];
  EXPECT_EQ(g["by"], "surface");
  EXPECT_NEAR(part.report["porosity"].get<double>(), g["porosity_mean"].get<double>(), 1e-3);
  const nlohmann::json& bands = g["profile"];
  ASSERT_EQ(bands.size(), 5u);
  EXPECT_NEAR(bands[4]["porosity_target"].get<double>(), 0.7, 1e-9);
  for (const auto* b : {&bands[0], &bands[4]})
    EXPECT_NEAR((*b)["porosity_nodes"].get<double>(), (*b)["porosity_target"].get<double>(),
                0.03)
        << b->dump();
  EXPECT_GT(bands[4]["porosity_nodes"].get<double>(),
            bands[0]["porosity_nodes"].get<double>() + 0.1);
  EXPECT_GT(part.report["sheet"]["thickness_from"].get<double>(),
            1.3 * part.report["sheet"]["thickness_to"].get<double>());
  EXPECT_THROW(design_graded_sheet(phi, d, ramp), std::invalid_argument);
  ramp.depth = 0.0;
  EXPECT_THROW(design_graded_sheet(phi, d, ramp, {}, &shape), std::invalid_argument);
}

// Two overlapping closed cubes in one STL (4^3 each, overlapping in 2^3) are their
// union, 120 and not the 128 their triangles sum to: the porosity holds over the union, and
// a skin follows only the union's surface (no wall along a face inside the other cube).
TEST(Part, OverlappingShellsFillTheirUnion) {
  TempDir dir("part_test");
  TriMesh two = box_mesh({0, 0, 0}, {4, 4, 4});
  const TriMesh b = box_mesh({2, 2, 2}, {6, 6, 6});
  for (const auto& t : b.triangles)
    two.triangles.push_back({t[0] + 8, t[1] + 8, t[2] + 8});
  two.vertices.insert(two.vertices.end(), b.vertices.begin(), b.vertices.end());
  write_stl(dir / "two.stl", two);
  ShapeFill shape;
  shape.mesh = read_stl(dir / "two.stl");
  ScaffoldDesign d;
  d.cell_size = 2.0;
  d.porosity = 0.6;
  d.morphometry = false;
  const Field phi = nodal("G", 16);
  for (const double skin : {0.0, 0.2}) {
    shape.skin = skin;
    const ScaffoldPart part = design_scaffold(phi, d, &shape);
    EXPECT_NEAR(part.report["shape"]["volume_triangles"].get<double>(), 128.0, 1e-6);
    EXPECT_NEAR(part.report["shape"]["volume"].get<double>(), 120.0, 0.3) << skin;
    const double solid = analyze_mesh(part.mesh).volume;
    EXPECT_NEAR(1.0 - solid / 120.0, 0.6, 2e-3) << skin;
    EXPECT_NEAR(part.report["porosity"].get<double>(), 0.6, 1e-3) << skin;
  }
}

// A target no level reaches is warned about without blaming a --skin that was not
// given (a rod of porosity 0.8 in a 0/1 field cannot be thickened to porosity 0.5).
TEST(Part, MissedPorosityWarningNamesTheSkinOnlyWithOne) {
  const Field rod = from_function(16, [](double x, double y, double) {
    return (x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5) < 0.0625 ? 1.0 : 0.0;
  });
  ScaffoldDesign d;
  d.cell_size = 1.0;
  d.size = {1.0, 1.0, 1.0};
  d.porosity = 0.5;
  d.morphometry = false;
  const ScaffoldPart part = design_scaffold(rod, d);
  ASSERT_GT(std::abs(part.report["porosity_error"].get<double>()), 1e-3);
  std::string all;
  for (const std::string& w : part.warnings) all += w + "\n";
  EXPECT_NE(all.find("no network level reaches it"), std::string::npos) << all;
  EXPECT_EQ(all.find("skin"), std::string::npos) << all;
}

// The part written as 3MF reads back through lib3mf with the same triangles and units.
TEST(Part, ThreeMfReadsBack) {
  ScaffoldDesign d;
  d.cell_size = 2.0;
  d.size = {4.0, 4.0, 3.0};
  d.morphometry = false;
  const ScaffoldPart part = design_scaffold(nodal("G", 16), d);
  TempDir dir("part_test");
  write_3mf(dir / "p.3mf", part.mesh, "mm", {"gyroid", "porosity=0.7", "cmcsurf test"});
  const Read3mf r = read_3mf(dir / "p.3mf");
  EXPECT_EQ(r.unit, "mm");
  EXPECT_EQ(r.triangles, part.mesh.triangles.size());
  EXPECT_EQ(r.build_items, 1u);
}

// Decimation to a budget (a quarter, a tenth) or a tolerance keeps a closed, manifold,
// one-piece solid within 0.5 % in volume, inside the budget, and reports the distance achieved
// (within the tolerance when one is given).
TEST(Part, DecimationKeepsTheSolid) {
  ScaffoldDesign d;
  d.cell_size = 1.0;
  d.size = {1.0, 1.0, 1.5};
  d.morphometry = false;
  const ScaffoldPart part = design_scaffold(nodal("G", 24), d);
  const double v = mesh_volume(part.mesh);
  for (const std::size_t divisor : {4, 10}) {
    DecimateParams p;
    p.max_triangles = part.mesh.triangles.size() / divisor;
    const Decimated dm = decimate_solid(part.mesh, p);
    EXPECT_TRUE(dm.applied);
    EXPECT_TRUE(dm.within_budget);
    EXPECT_LE(dm.triangles_after, p.max_triangles);
    expect_clean_solid(dm.mesh);
    EXPECT_EQ(mesh_shell_count(dm.mesh), 1u);
    EXPECT_LE(std::abs(mesh_volume(dm.mesh) / v - 1.0), 5e-3);
    EXPECT_GT(dm.error, 0.0);
    EXPECT_LT(dm.error, 0.02);  // of a unit cell
    EXPECT_EQ(dm.error, std::max(dm.error_input_to_output, dm.error_output_to_input));
    EXPECT_GT(dm.error_output_to_input, 0.0);
  }
  DecimateParams p;
  p.tolerance = 0.002;
  const Decimated dm = decimate_solid(part.mesh, p);
  EXPECT_TRUE(dm.applied);
  EXPECT_LT(dm.triangles_after, part.mesh.triangles.size() / 2);
  EXPECT_LE(dm.error, p.tolerance * 1.0001);
  expect_clean_solid(dm.mesh);
  EXPECT_THROW(decimate_solid(part.mesh, {}), std::invalid_argument);
}

// A budget the input already meets: nothing is attempted (no failed retries) and the report
// says so.
TEST(Part, DecimationWithinBudgetReturnsTheInput) {
  ScaffoldDesign d;
  d.cell_size = 1.0;
  d.size = {1.0, 1.0, 1.0};
  d.morphometry = false;
  const ScaffoldPart part = design_scaffold(nodal("P", 16), d);
  DecimateParams p;
  p.max_triangles = part.mesh.triangles.size();
  const Decimated dm = decimate_solid(part.mesh, p);
  EXPECT_FALSE(dm.applied);
  EXPECT_EQ(dm.attempts, 0);
  EXPECT_TRUE(dm.within_budget);
  EXPECT_EQ(dm.triangles_after, part.mesh.triangles.size());
  EXPECT_EQ(dm.mesh.triangles, part.mesh.triangles);
  EXPECT_NE(dm.note.find("within the budget"), std::string::npos);
}

// The decimation error is measured both ways. A flat square finely triangulated (a) against a
// coarse pyramid of height 0.1 over it (b): b's apex is 0.1 from a, while a's points are all
// nearer than that to b, so a one-sided measure from a would miss it; the bound holds.
TEST(Part, DecimationErrorIsSymmetric) {
  TriMesh a, b;
  const int n = 20;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) a.vertices.push_back({double(i) / n, double(j) / n, 0.0});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::uint32_t v = std::uint32_t(j * (n + 1) + i);
      a.triangles.push_back({v, v + 1, v + n + 2});
      a.triangles.push_back({v, v + n + 2, v + n + 1});
    }
  b.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 0.1}};
  b.triangles = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
  const SymmetricDistance d = symmetric_distance(a, b);
  EXPECT_NEAR(d.b_to_a, 0.1, 1e-12);
  EXPECT_LT(d.a_to_b, 0.1);
  EXPECT_GT(d.a_to_b, 0.05);  // the centre of a: 0.1 cos(atan(0.2)) = 0.098 below the apex's faces
  EXPECT_LE(d.spacing, std::sqrt(2.0) / n + 1e-12);
  // Swapped, the directions swap.
  const SymmetricDistance e = symmetric_distance(b, a);
  EXPECT_NEAR(e.a_to_b, 0.1, 1e-12);
}

std::vector<std::uint8_t> voxels(int n, const std::function<bool(double, double, double)>& in) {
  std::vector<std::uint8_t> v(std::size_t(n) * n * n);
  for_each_cell(n, [&](int i, int j, int k) {
    v[(std::size_t(k) * n + j) * n + i] = in((i + 0.5) / n, (j + 0.5) / n, (k + 0.5) / n);
  });
  return v;
}

// Local thickness (diameters 2 r - 1 voxels for balls of radius r to the nearest voxel centre
// outside): a flat slab 8 voxels thick and its 24-voxel complement read their thickness, and
// a cylindrical channel of radius 6.5 voxels (axis on a voxel centre) its diameter 13, each
// everywhere within one voxel.
TEST(Morphometry, SlabAndChannelWithinOneVoxel) {
  const int n = 32;
  const auto slab =
      voxels(n, [](double, double, double z) { return std::abs(z - 0.5) < 4.0 / 32; });
  const ThicknessStats s = thickness_stats(local_thickness(slab, n), slab, 1.0);
  EXPECT_NEAR(s.fraction, 8.0 / 32, 1e-12);
  EXPECT_NEAR(s.mean, 8.0, 1.0);
  EXPECT_NEAR(s.min, 8.0, 1.0);
  EXPECT_NEAR(s.max, 8.0, 1.0);
  std::vector<std::uint8_t> gap(slab.size());
  for (std::size_t c = 0; c < gap.size(); ++c) gap[c] = !slab[c];
  const ThicknessStats g = thickness_stats(local_thickness(gap, n), gap, 1.0);
  EXPECT_NEAR(g.mean, 24.0, 1.0);
  EXPECT_NEAR(g.min, 24.0, 1.0);
  const double axis = 0.5 + 0.5 / n;
  const auto channel = voxels(n, [&](double x, double y, double) {
    return std::hypot(x - axis, y - axis) < 6.5 / n;
  });
  const ThicknessStats c = thickness_stats(local_thickness(channel, n), channel, 1.0);
  EXPECT_NEAR(c.mean, 13.0, 1.0);
  EXPECT_NEAR(c.min, 13.0, 1.0);
  EXPECT_NEAR(c.max, 13.0, 1.0);
}

// Local thickness against its definition, brute force: at each voxel the largest 2 r - 1 over
// the balls |x - c| < r = sqrt(edt2(c)) that contain it; the opening-based kernel merges radii
// closer than 1/8 voxel, so it may read up to 1/4 voxel less, never more.
TEST(Morphometry, LocalThicknessMatchesTheBallDefinition) {
  const int n = 12;
  const auto blobs = voxels(n, [](double x, double y, double z) {
    return std::sin(6.283 * x) * std::cos(6.283 * y) + std::sin(6.283 * y) * std::cos(6.283 * z) +
               std::sin(6.283 * z) * std::cos(6.283 * x) > -0.4;
  });
  const std::vector<double> d2 = periodic_edt2(blobs, n);
  const std::vector<double> t = local_thickness(blobs, n);
  for (int x = 0; x < n * n * n; ++x) {
    if (!blobs[x]) {
      EXPECT_EQ(t[x], 0.0);
      continue;
    }
    double best = 1.0;
    for (int c = 0; c < n * n * n; ++c) {
      if (!blobs[c]) continue;
      double s = 0;
      for (int a : {1, n, n * n}) {
        int dx = std::abs(c / a % n - x / a % n);
        dx = std::min(dx, n - dx);
        s += dx * dx;
      }
      if (s < d2[c]) best = std::max(best, 2.0 * std::sqrt(d2[c]) - 1.0);
    }
    EXPECT_LE(t[x], best + 1e-12) << x;
    EXPECT_GE(t[x], best - 0.25 - 1e-12) << x;
  }
}

// The distance transform against brute force on a random pattern.
TEST(Morphometry, DistanceTransformMatchesBruteForce) {
  const int n = 8;
  std::vector<std::uint8_t> in(n * n * n);
  unsigned state = 12345;
  for (auto& v : in) v = (state = state * 1103515245u + 12345u) >> 16 & 7 ? 1 : 0;
  const std::vector<double> d2 = periodic_edt2(in, n);
  for (int c = 0; c < n * n * n; ++c) {
    double best = 1e30;
    for (int o = 0; o < n * n * n; ++o) {
      if (in[o]) continue;
      double s = 0;
      for (int a : {1, n, n * n}) {
        int dx = std::abs(c / a % n - o / a % n);
        dx = std::min(dx, n - dx);
        s += dx * dx;
      }
      best = std::min(best, s);
    }
    EXPECT_EQ(d2[c], in[c] ? best : 0.0) << c;
  }
}

}  // namespace
}  // namespace cmcsurf
