#include "pipeline/sweep_groups.h"

#include <gtest/gtest.h>

#include <cmath>

namespace cmcsurf {
namespace {

SweepParams sweep_of(int surfaces, int fractions, bool continuation) {
  SweepParams p;
  for (int s = 0; s < surfaces; ++s) p.surfaces.push_back(s % 2 ? "D" : "P");
  for (int f = 0; f < fractions; ++f) p.fractions.push_back(0.3 + 0.1 * f);
  p.continuation = continuation;
  return p;
}

TEST(SweepGroups, UnitsAreMembersOrWholeFamilies) {
  EXPECT_EQ(sweep_units(sweep_of(2, 2, false)),
            (std::vector<std::vector<int>>{{0}, {1}, {2}, {3}}));
  EXPECT_EQ(sweep_units(sweep_of(2, 3, true)),
            (std::vector<std::vector<int>>{{0, 1, 2}, {3, 4, 5}}));
}

TEST(SweepGroups, DealsMembersRoundRobinAndFamiliesWhole) {
  EXPECT_EQ(assign_members(sweep_of(2, 2, false), 2), (std::vector<int>{0, 1, 0, 1}));
  EXPECT_EQ(assign_members(sweep_of(3, 11, false), 33), [] {
    std::vector<int> g(33);
    for (int i = 0; i < 33; ++i) g[i] = i;
    return g;
  }());
  // 3 families of 2 on 2 groups: each family on one group, the third to the first group.
  EXPECT_EQ(assign_members(sweep_of(3, 2, true), 2), (std::vector<int>{0, 0, 1, 1, 0, 0}));
  EXPECT_EQ(assign_members(sweep_of(1, 5, false), 1), (std::vector<int>(5, 0)));
  // More groups than units: the last groups get nothing.
  EXPECT_EQ(assign_members(sweep_of(1, 2, false), 4), (std::vector<int>{0, 1}));
  EXPECT_THROW(assign_members(sweep_of(1, 2, false), 0), std::invalid_argument);
  // Every group's share differs from another's by at most one unit of members.
  const std::vector<int> g = assign_members(sweep_of(3, 7, false), 4);
  std::vector<int> count(4, 0);
  for (int x : g) ++count[x];
  EXPECT_EQ(count, (std::vector<int>{6, 5, 5, 5}));
}

TEST(SweepGroups, DefaultGroupsUseTheRanksInAsFewRounds) {
  const auto any = [](int) { return true; };
  EXPECT_EQ(default_groups(1, 4, any), 1);
  EXPECT_EQ(default_groups(4, 4, any), 4);   // a member per rank
  EXPECT_EQ(default_groups(4, 2, any), 2);   // two groups of two
  EXPECT_EQ(default_groups(4, 1, any), 1);   // one member on all four
  EXPECT_EQ(default_groups(4, 33, any), 4);
  EXPECT_EQ(default_groups(4, 3, any), 2);   // 2 rounds either way: groups of two
  EXPECT_EQ(default_groups(12, 7, any), 4);  // 6 groups take 2 rounds, so do 4 of 3 ranks
  EXPECT_EQ(default_groups(33, 33, any), 33);
  EXPECT_EQ(default_groups(64, 33, any), 32);
  // Group sizes that do not split the grid are skipped, down to idle groups of one.
  const auto up_to_two = [](int q) { return q <= 2; };
  EXPECT_EQ(default_groups(8, 2, up_to_two), 4);  // 4 groups of 2, two of them idle
  EXPECT_EQ(default_groups(8, 8, up_to_two), 8);
  EXPECT_EQ(default_groups(4, 1, [](int q) { return q == 1; }), 4);
  EXPECT_THROW(default_groups(4, 1, [](int) { return false; }), std::logic_error);
}

TEST(SweepGroups, OneProcessRunsAnyMember) {
  RunParams p;
  p.grid = 6;  // no split would hold it
  p.smoother = SweepOrder::kLexicographic;
  EXPECT_EQ(group_grid_problem(p, 1), "");
  EXPECT_NE(group_grid_problem(p, 2).find("--smoother"), std::string::npos);
}

TEST(SweepGroups, RowsSurviveTheTripExactly) {
  GroupRows g;
  g.status = 1;
  g.message = "member D_0.40 diverged";
  g.kept = 2;
  g.resumed = 1;
  GroupRows::Row a;
  a.index = 3;
  a.report = {{"area", 0.1 + 0.2}, {"mean_curvature", -1.0 / 3.0}, {"member", "D_0.40"},
              {"converged", true}, {"steps", 17}, {"process_grid", {1, 1, 2}}};
  GalleryMember tile;
  tile.surface = "D";
  tile.name = "D_0.40";
  tile.alpha = 0.4;
  tile.mean_curvature = std::nextafter(0.5, 1.0);
  tile.relaxed.positions = {{0.1f, 0.2f, 0.3f}, {1.0f, 2.0f, 3.0f}};
  tile.relaxed.normals = {{0.0f, 0.0f, 1.0f}, {1.0f, 0.0f, 0.0f}};
  tile.relaxed.curvature = {0.25f, -0.125f};
  tile.relaxed.triangles = {{0u, 1u, 1u}};
  tile.relaxed.lattice_cells = 16;
  tile.relaxed.origin = 1.0f / 64.0f;
  a.tile = tile;
  GroupRows::Row b;
  b.index = 5;
  b.report = {{"area", 1e-300}};
  g.rows = {a, b};
  const GroupRows back = unpack_group_rows(pack_group_rows(g));
  EXPECT_EQ(back.status, 1);
  EXPECT_EQ(back.message, g.message);
  EXPECT_EQ(back.kept, 2);
  EXPECT_EQ(back.resumed, 1);
  ASSERT_EQ(back.rows.size(), 2u);
  EXPECT_EQ(back.rows[0].index, 3);
  EXPECT_EQ(back.rows[0].report, a.report);  // doubles bit for bit
  EXPECT_EQ(back.rows[0].report["area"].get<double>(), 0.1 + 0.2);
  ASSERT_TRUE(back.rows[0].tile.has_value());
  const GalleryMember& t = *back.rows[0].tile;
  EXPECT_EQ(t.name, "D_0.40");
  EXPECT_EQ(t.mean_curvature, tile.mean_curvature);
  EXPECT_EQ(t.relaxed.positions, tile.relaxed.positions);
  EXPECT_EQ(t.relaxed.normals, tile.relaxed.normals);
  EXPECT_EQ(t.relaxed.curvature, tile.relaxed.curvature);
  EXPECT_EQ(t.relaxed.triangles, tile.relaxed.triangles);
  EXPECT_EQ(t.relaxed.lattice_cells, 16);
  EXPECT_EQ(t.relaxed.origin, tile.relaxed.origin);
  EXPECT_FALSE(back.rows[1].tile.has_value());
  EXPECT_EQ(back.rows[1].report["area"].get<double>(), 1e-300);
  EXPECT_THROW(unpack_group_rows("not msgpack"), std::runtime_error);
  EXPECT_THROW(unpack_group_rows(""), std::runtime_error);
}

}  // namespace
}  // namespace cmcsurf
