#include "pipeline/sweep.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "io/run_report.h"

namespace cmcsurf {
namespace {

TEST(Sweep, ParsesRangesAndLists) {
  const std::vector<double> r = parse_volume_fractions("0.25:0.75:0.05");
  ASSERT_EQ(r.size(), 11u);
  EXPECT_EQ(r.front(), 0.25);
  EXPECT_EQ(r[2], 0.35);  // rounded, not 0.35000000000000003
  EXPECT_EQ(r.back(), 0.75);
  EXPECT_EQ(parse_volume_fractions("0.3,0.5,0.7"), (std::vector<double>{0.3, 0.5, 0.7}));
  EXPECT_EQ(parse_volume_fractions("0.4"), std::vector<double>{0.4});
  EXPECT_EQ(parse_volume_fractions("0.5:0.5:0.1"), std::vector<double>{0.5});
  EXPECT_EQ(parse_volume_fractions("0.2:0.5:0.2").size(), 2u);  // stop not reached exactly
}

TEST(Sweep, RejectsBadRanges) {
  for (const char* bad : {"0.75:0.25:0.05", "0.2:0.8:0", "0.2:0.8:-0.1", "0:0.5:0.1",
                          "0.5:1:0.1", "a:0.5:0.1", "0.2:0.8", "0.2:0.4:0.1:0.1", "", "0.3,,0.5",
                          "1.2", "0.3,1", "nan", "0.1:0.9:1e-6"})
    EXPECT_THROW(parse_volume_fractions(bad), std::invalid_argument) << bad;
}

TEST(Sweep, ParsesSurfaceLists) {
  EXPECT_EQ(parse_surface_list("P,D,G"), (std::vector<std::string>{"P", "D", "G"}));
  const auto s = parse_surface_list("G, expr:max(cos(x), cos(y)) - 0.5");
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[1], "expr:max(cos(x), cos(y)) - 0.5");
  EXPECT_THROW(parse_surface_list("P,Q"), std::invalid_argument);
  EXPECT_THROW(parse_surface_list("P,sphere"), std::invalid_argument);  // no volume fraction
  EXPECT_THROW(parse_surface_list("P,"), std::invalid_argument);
}

// A sweep read back from sweep.json gets the command line's checks.
TEST(Sweep, ChecksASweepReadBack) {
  SweepParams ok;
  ok.surfaces = {"P", "expr:cos(x)+cos(y)+cos(z)"};
  ok.fractions = {0.3, 0.5};
  EXPECT_NO_THROW(check_sweep_params(ok));
  auto refused = [&](const std::function<void(SweepParams&)>& edit) {
    SweepParams p = ok;
    edit(p);
    EXPECT_THROW(check_sweep_params(p), std::invalid_argument);
  };
  refused([](SweepParams& p) { p.surfaces.clear(); });
  refused([](SweepParams& p) { p.surfaces = {"sphere"}; });  // no nodal formula
  refused([](SweepParams& p) { p.surfaces = {"nonesuch"}; });
  refused([](SweepParams& p) { p.fractions.clear(); });
  refused([](SweepParams& p) { p.fractions = {0.3, 1.5}; });
  refused([](SweepParams& p) { p.fractions = {std::nan("")}; });
  refused([](SweepParams& p) { p.fractions.assign(1001, 0.5); });
  refused([](SweepParams& p) { p.run.epsilon = -1.0; });
  refused([](SweepParams& p) { p.run.grid = 50; });
}

TEST(Sweep, MemberNames) {
  EXPECT_EQ(member_name("G", 0, 0.3), "G_0.30");
  EXPECT_EQ(member_name("P", 1, 0.75), "P_0.75");
  EXPECT_EQ(member_name("D", 0, 0.325), "D_0.325");
  EXPECT_EQ(member_name("expr:cos(x)", 2, 0.5), "expr2_0.50");
}

// One G member at alpha and at 1 - alpha, 32^3 (eps = 0.64 h as the default at 64^3).
struct GyroidPair {
  RunParams p;
  RunResult low, high;
  GyroidPair() {
    p.surface = std::string("G");  // a move: GCC 12 warns falsely (-Wrestrict) on = "G" here
    p.grid = 32;
    p.epsilon = 0.02;
    p.volume_fraction = 0.3;
    low = run_cmc(p);
    p.volume_fraction = 0.7;
    high = run_cmc(p);
    p.volume_fraction = 0.3;
  }
};
const GyroidPair& gyroid_pair() {
  static const GyroidPair pair;
  return pair;
}

TEST(Sweep, MemberNamesReadBackArePlainFolderNames) {
  check_member_name("G_0.30", "sweep.json");
  check_member_name("expr2_0.325", "sweep.json");
  check_member_name("DoubleP_1e-05", "sweep.json");
  const std::vector<std::string> bads = {"../victim/G_0.30", "/etc/G_0.30", "a/b", "..", ".", "",
                                         std::string("G\0_0.30", 8), "G_0.30\n",
                                         std::string(256, 'G')};
  for (const std::string& bad : bads) {
    try {
      check_member_name(bad, "DIR/sweep.json");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const std::invalid_argument& e) {
      const std::string why = e.what();
      EXPECT_NE(why.find("DIR/sweep.json"), std::string::npos) << why;
      EXPECT_NE(why.find("member name"), std::string::npos) << why;
    }
  }
  EXPECT_THROW(checked_member_name("../victim/G", 0, 0.3, "sweep.json"), std::invalid_argument);
  EXPECT_EQ(checked_member_name("expr:cos(x)/2", 1, 0.5, "sweep.json"), "expr1_0.50");
}

// A sweep.json as cmd_sweep writes it (the parameters are the run defaults at grid 16).
nlohmann::json sweep_json() {
  RunParams p;
  p.grid = 16;
  nlohmann::json params = params_json(p);
  params.erase("surface");
  params.erase("volume_fraction");
  return {{"members", 2},
          {"surfaces", {"G"}},
          {"volume_fractions", {0.3, 0.5}},
          {"continuation", true},
          {"threads", 2},
          {"wall_seconds", 1.5},
          {"version", "x"},
          {"parameters", params},
          {"outputs",
           {{"threads", 2},
            {"float32", true},
            {"no_preview", false},
            {"no_report", true},
            {"no_plot", true},
            {"python", "/tmp/evil"},
            {"plot_script", "/tmp/evil.py"},
            {"checkpoint_every", 60.0},
            {"properties", true},
            {"properties_solid", "sheet"},
            {"properties_porosity", "0.6,0.8"},
            {"properties_grid_check", true}}}};
}

TEST(Sweep, ParsesSweepJsonWithoutExecutables) {
  const SweepJson s = parse_sweep_json(sweep_json());
  EXPECT_EQ(s.sweep.surfaces, std::vector<std::string>{"G"});
  EXPECT_EQ(s.sweep.fractions, (std::vector<double>{0.3, 0.5}));
  EXPECT_TRUE(s.sweep.continuation);
  EXPECT_EQ(s.sweep.run.grid, 16);
  EXPECT_EQ(s.outputs.value("threads", 0), 2);
  EXPECT_EQ(s.outputs.value("checkpoint_every", 0.0), 60.0);
  EXPECT_TRUE(s.outputs.value("float32", false));
  EXPECT_FALSE(s.outputs.contains("python"));
  EXPECT_FALSE(s.outputs.contains("plot_script"));
  // the --properties stage is restored too (it was dropped, so a resume lost the chart)
  EXPECT_TRUE(s.outputs.value("properties", false));
  EXPECT_TRUE(s.outputs.value("properties_grid_check", false));
  EXPECT_EQ(s.outputs.value("properties_solid", ""), "sheet");
  EXPECT_EQ(s.outputs.value("properties_porosity", ""), "0.6,0.8");
}

TEST(Sweep, SweepJsonOutOfRangeNamesTheKey) {
  auto refused = [](const std::function<void(nlohmann::json&)>& edit, const std::string& key) {
    nlohmann::json j = sweep_json();
    edit(j);
    try {
      parse_sweep_json(j);
      ADD_FAILURE() << "accepted " << j.dump();
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  refused([](auto& j) { j["parameters"]["max_steps"] = 4294967298ull; }, "'max_steps'");
  refused([](auto& j) { j["parameters"]["grid"] = 16.5; }, "'grid'");
  refused([](auto& j) { j["outputs"]["threads"] = 4294967298ull; }, "'outputs.threads'");
  refused([](auto& j) { j["outputs"]["threads"] = 5000; }, "'outputs.threads'");
  refused([](auto& j) { j["outputs"]["checkpoint_every"] = -1; }, "'outputs.checkpoint_every'");
  refused([](auto& j) { j["outputs"]["float32"] = 1; }, "'outputs.float32'");
  refused([](auto& j) { j["outputs"]["python"] = 3; }, "'outputs.python'");
  refused([](auto& j) { j["outputs"]["properties_porosity"] = 0.7; },
          "'outputs.properties_porosity'");
  refused([](auto& j) { j["outputs"] = 3; }, "'outputs'");
  refused([](auto& j) { j["members"] = 3; }, "'members'");
  refused([](auto& j) { j["members"] = -1; }, "'members'");
  refused([](auto& j) { j["threads"] = -1; }, "'threads'");
  refused([](auto& j) { j["wall_seconds"] = -1; }, "'wall_seconds'");
  refused([](auto& j) { j["continuation"] = "yes"; }, "'continuation'");
  refused([](auto& j) { j["volume_fractions"][1] = "0.5"; }, "'volume_fractions[1]'");
  refused([](auto& j) { j["volume_fractions"][1] = 1.5; }, "1.5");
  refused([](auto& j) { j["surfaces"][0] = 7; }, "'surfaces[0]'");
  refused([](auto& j) { j["surfaces"][0] = "../victim/G"; }, "../victim/G");
  refused([](auto& j) { j.erase("parameters"); }, "'parameters'");
  refused([](auto& j) { j["mpi"] = {{"ranks", 0}}; }, "'mpi.ranks'");
}

TEST(Sweep, BalancedSurfaceIsSymmetricInVolumeFraction) {
  // G is balanced: x -> -x maps F - 1/2 to -(F - 1/2) and the grid onto itself, and the
  // Cahn-Hilliard problem is symmetric under phi -> 1 - phi, so the members at alpha and
  // 1 - alpha are mirror images up to the bisection tolerance (1e-6 in V_ave, removed by the
  // shift), the V-cycle tolerance and round-off: equal area, opposite mean curvature. We allow
  // 1e-5 relative, far above those (observed: ~1e-12) and far below the family's variation.
  const GyroidPair& g = gyroid_pair();
  EXPECT_TRUE(g.low.converged);
  EXPECT_NEAR(g.low.final.area, g.high.final.area, 1e-5 * g.low.final.area);
  EXPECT_NEAR(g.low.final.mean_curvature, -g.high.final.mean_curvature,
              1e-5 * std::abs(g.low.final.mean_curvature));
  EXPECT_GT(g.low.final.mean_curvature, 0.5);  // phase 1 is the minority: convex, H > 0
}

TEST(Sweep, RelaxedSurfaceIsCloserToCmcThanTheNodalOne) {
  const GyroidPair& g = gyroid_pair();
  const CmcQuality q = measure_cmc_quality(g.low.phi, g.p);
  ASSERT_TRUE(q.has_nodal);
  EXPECT_NEAR(q.nodal_volume_fraction, g.low.final.volume_fraction, 1e-6);
  // The relaxed surface's local H averages to the run's mean curvature, with a spread well
  // below the nodal surface's (a CMC surface has none; at 32^3, eps = 0.64 h, what remains is
  // mostly the discrete profile's imprint on the estimator).
  EXPECT_NEAR(q.relaxed.mean, g.low.final.mean_curvature, 1e-12);
  EXPECT_GT(q.nodal.std, 3.0 * q.relaxed.std);
  EXPECT_GT(q.seconds, 0.0);
  // Nodal G is within ~0.1% of the CMC area, below what 32^3 resolves; P's excess is ~0.35%.
  EXPECT_NEAR(q.nodal_area, g.low.final.area, 2e-3 * g.low.final.area);
  RunParams p = g.p;
  p.surface = "P";
  const RunResult pr = run_cmc(p);
  const CmcQuality pq = measure_cmc_quality(pr.phi, p);
  EXPECT_GT(pq.nodal_area, pr.final.area * (1 + 1e-3));
  EXPECT_LT(pq.nodal_area, pr.final.area * (1 + 1e-2));
}

TEST(Sweep, ContinuationMemberReportsItsVolumeCorrections) {
  // A continued member goes through the same secant iteration as run_cmc: its iterates are
  // recorded and it ends within volume_tol of its target.
  const GyroidPair& g = gyroid_pair();
  RunParams p = g.p;
  p.volume_fraction = 0.35;
  const RunResult r = run_from_neighbour(g.low.phi, 0.3, p);
  EXPECT_TRUE(r.volume_constrained);
  ASSERT_GE(r.volume_iterates.size(), 2u);  // the shift alone leaves V off by ~1e-3
  EXPECT_TRUE(r.volume_converged);
  EXPECT_NEAR(r.final.volume_fraction, 0.35, p.volume_tol);
  EXPECT_EQ(r.volume_iterates.back().volume_fraction, r.final.volume_fraction);
  EXPECT_TRUE(r.final.sharp);
}

}  // namespace
}  // namespace cmcsurf
