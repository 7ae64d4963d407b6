#include "io/run_report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <variant>

namespace cmcsurf {
namespace {

TEST(RunReport, SweepCsvHasEveryScalarMainColumnsFirst) {
  nlohmann::json a = {{"surface", "G"}, {"area", 3.1}, {"steps", 7}, {"converged", true},
                      {"parameters", {{"grid", 16}}}, {"nodal_area", nullptr}};
  nlohmann::json b = a;
  b["extra"] = "x,y";
  const std::string csv = sweep_csv({a, b});
  const std::string header = csv.substr(0, csv.find('\n'));
  EXPECT_EQ(header.rfind("surface,volume_fraction_target,volume_fraction,area,area_error,"
                         "mean_curvature,", 0), 0u);
  EXPECT_NE(header.find(",steps"), std::string::npos);
  EXPECT_NE(header.find(",extra"), std::string::npos);
  EXPECT_EQ(header.find("parameters"), std::string::npos);  // objects are not scalars
  EXPECT_NE(csv.find("G,,,3.1000000000000001,,"), std::string::npos);
  EXPECT_NE(csv.find("\"x,y\""), std::string::npos);
}

TEST(RunReport, MeasuresWithoutAnErrorEstimateWriteNull) {
  Measures m;
  m.sharp = true;
  m.area = 2.0;
  m.area_error = std::numeric_limits<double>::quiet_NaN();
  m.mean_curvature_error = 1e-3;
  const nlohmann::json j = measures_json(m);
  EXPECT_TRUE(j["area_error"].is_null());
  EXPECT_DOUBLE_EQ(j["mean_curvature_error"].get<double>(), 1e-3);
  EXPECT_DOUBLE_EQ(j["area"].get<double>(), 2.0);
  Measures diffuse_only;  // a relaxation's intermediate measures carry no sharp keys
  EXPECT_FALSE(measures_json(diffuse_only).contains("area"));
  EXPECT_TRUE(measures_json(diffuse_only).contains("area_diffuse"));
}

// A gyroid's phases (chi -4 each) as the keys state them: the surface's chi is the phases'
// sum, its genus per piece, Gauss-Bonnet against 2 pi chi.
TEST(RunReport, TopologyAndStandardNumbersKeys) {
  Measures m;
  m.sharp = true;
  m.area = 3.0915;
  m.euler_characteristic = -4;
  m.euler_characteristic_phase2 = -4;
  m.components_phase1 = 1;
  m.components_phase2 = 1;
  m.surface_components = 1;
  m.gaussian_curvature_integral = -16 * std::numbers::pi * 1.01;
  m.willmore_energy = 0.5;
  nlohmann::json j = measures_json(m);
  EXPECT_EQ(j["euler_characteristic"], -4);  // phase 1's, as before
  EXPECT_EQ(j["genus"], 5);
  EXPECT_EQ(j["euler_characteristic_surface"], -8);
  EXPECT_DOUBLE_EQ(j["genus_surface"].get<double>(), 5.0);
  EXPECT_NEAR(j["homogeneity_index"].get<double>(), 0.7667, 5e-5);  // G, Hyde's sigma
  EXPECT_NEAR(j["gauss_bonnet_error"].get<double>(), 0.01, 1e-12);
  EXPECT_NEAR(j["mean_gaussian_curvature"].get<double>(), -16 * std::numbers::pi * 1.01 / 3.0915,
              1e-12);
  EXPECT_DOUBLE_EQ(j["willmore_energy"].get<double>(), 0.5);
  // Two surfaces of genus 5 (a double gyroid's): chi -16 over 2 pieces.
  m.euler_characteristic = m.euler_characteristic_phase2 = -8;
  m.components_phase1 = 2;
  m.surface_components = 2;
  j = measures_json(m);
  EXPECT_DOUBLE_EQ(j["genus_surface"].get<double>(), 5.0);
  EXPECT_EQ(j["components_phase1"], 2);
  // Not computed (a large decomposed grid), or a surface with chi 0: null, not a number.
  m.components_phase1 = m.components_phase2 = m.surface_components = -1;
  m.euler_characteristic = m.euler_characteristic_phase2 = 0;
  j = measures_json(m);
  EXPECT_TRUE(j["components_phase1"].is_null());
  EXPECT_TRUE(j["genus_surface"].is_null());
  EXPECT_TRUE(j["homogeneity_index"].is_null());
  EXPECT_TRUE(j["gauss_bonnet_error"].is_null());
  // The truncated nodal start: topology, but no curvature integrals.
  EXPECT_FALSE(measures_json(m, false).contains("willmore_energy"));
  EXPECT_TRUE(measures_json(m, false).contains("euler_characteristic_surface"));
}

}  // namespace
}  // namespace cmcsurf

namespace cmcsurf {
namespace {

TEST(RunReport, ParametersReadBackExactly) {
  RunParams p;
  p.surface = "expr:cos(x)";
  p.volume_fraction = 0.3;
  p.grid = 96;
  p.epsilon = 0.013;
  p.stop = StopRule::kPhi;
  p.smoother = SweepOrder::kLexicographic;
  p.constrain = Constraint::kMass;
  p.seed = 18446744073709551615ull;
  p.solver.rtol = 1e-2;
  p.solver.extrapolate = true;
  p.solver.fas.coarsest_reduction = 1e-7;
  p.coarse_levels = 2;
  p.fast = true;
  EXPECT_EQ(params_json(params_from_json(params_json(p))), params_json(p));
  nlohmann::json j = params_json(p);
  j.erase("surface");  // a sweep's shared parameters: the member's come from the base
  RunParams base;
  base.surface = "D";
  EXPECT_EQ(params_from_json(j, base).surface, "D");
  j["stop"] = "energy";
  EXPECT_THROW(params_from_json(j), std::runtime_error);
  j = params_json(p);
  j.erase("grid");
  EXPECT_THROW(params_from_json(j), std::runtime_error);
  // Values the command line would refuse are refused here too (check_run_params).
  for (const auto& [key, bad] : {std::pair<const char*, nlohmann::json>{"epsilon", 0.0},
                                 {"grid", 50},
                                 {"tol", std::numeric_limits<double>::infinity()},
                                 {"dt_factor", -1.0},
                                 {"coarse_levels", 5},
                                 {"pre_sweeps", 0}}) {
    j = params_json(p);
    j[key] = bad;
    if (std::string(key) == "pre_sweeps") j["post_sweeps"] = 0;
    EXPECT_THROW(params_from_json(j), std::runtime_error) << key << " = " << bad;
  }
}

TEST(RunReport, IntegersOutsideTheirTypeAreRefusedNotWrapped) {
  // max_steps 2^32 + 2 used to wrap to 2 in the int it is read into.
  const nlohmann::json good = params_json(RunParams{});
  auto why = [&](const char* key, const nlohmann::json& value) -> std::string {
    nlohmann::json j = good;
    j[key] = value;
    try {
      params_from_json(j);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  };
  const std::string wrapped = why("max_steps", 4294967298ull);
  EXPECT_NE(wrapped.find("'max_steps'"), std::string::npos) << wrapped;
  EXPECT_NE(wrapped.find("4294967298"), std::string::npos) << wrapped;
  EXPECT_NE(why("max_steps", -4294967294ll), "");
  EXPECT_NE(why("grid", 64.5), "");
  EXPECT_NE(why("grid", 4294967360ull), "");  // 2^32 + 64
  EXPECT_NE(why("seed", -1), "");
  EXPECT_NE(why("seed", 1.5), "");
  EXPECT_NE(why("pre_sweeps", 4294967298ull), "");
  EXPECT_NE(why("extrapolate", 1), "");
  EXPECT_EQ(why("seed", 18446744073709551615ull), "");
  EXPECT_EQ(why("dt_factor", 1), "");  // an integer is a number
}

TEST(RunReport, HistoryRowsAndStagesReadBackExactly) {
  StepRecord r;
  r.step = 17;
  r.stage = RunStage::kPrerelax;
  r.coarse_grids = {16, 32};  // taken on 16, carried through 32, of a run on 64
  r.time = 0.1;
  r.dt = 1.0 / 3.0;
  r.area = 3.0836526295383719;
  r.d_area = -2.4731220488183325e-05;
  r.d_phi = 5.6e-05;
  r.energy = 2.57;
  r.mass = 0.47;
  r.volume_fraction = 0.45;
  r.vcycles = 3;
  r.residual = 1.951626e-01;
  r.elapsed = 0.25;
  r.equilibrium_residual = 2.3131822319629475e-04;
  EXPECT_EQ(stage_text(r), "prerelax@16@32");
  StepRecord back;
  for (const HistoryColumnInfo& c : history_column_table()) {
    nlohmann::json v;
    std::visit([&](const auto& x) { v = x; }, history_value(r, c.id));
    set_history_value(back, c.id, v);
  }
  for (const HistoryColumnInfo& c : history_column_table())
    EXPECT_EQ(history_value(back, c.id), history_value(r, c.id)) << c.name;
  EXPECT_EQ(back.coarse_grids, r.coarse_grids);
  EXPECT_EQ(back.stage, RunStage::kPrerelax);
  // A step the stop rule did not measure: NaN, which JSON writes as null, reads back as NaN.
  r.equilibrium_residual = std::nan("");
  nlohmann::json unmeasured;
  std::visit([&](const auto& x) { unmeasured = x; },
             history_value(r, HistoryColumn::kEquilibriumResidual));
  set_history_value(back, HistoryColumn::kEquilibriumResidual, unmeasured);
  EXPECT_TRUE(std::isnan(back.equilibrium_residual));
  set_history_value(back, HistoryColumn::kEquilibriumResidual, nlohmann::json());
  EXPECT_TRUE(std::isnan(back.equilibrium_residual));
  for (const char* bad : {"relay", "relax@", "relax@x", "relax@16@", "@16", "relax@1"})
    EXPECT_THROW(set_history_value(back, HistoryColumn::kStage, bad), std::runtime_error) << bad;
  set_history_value(back, HistoryColumn::kStage, "volume");
  EXPECT_EQ(back.stage, RunStage::kVolume);
  EXPECT_TRUE(back.coarse_grids.empty());
}

}  // namespace
}  // namespace cmcsurf
