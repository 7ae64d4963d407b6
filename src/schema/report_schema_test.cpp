#include "schema/report_schema.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

namespace cmcsurf {
namespace {

TEST(ReportSchema, KeysAreUniqueAndViewsNameKeysOfTheTable) {
  std::set<std::string_view> keys;
  for (const ReportKey& k : report_key_table()) {
    EXPECT_TRUE(keys.insert(k.key).second) << k.key;
    EXPECT_FALSE(k.label.empty()) << k.key;
    if (!k.error_key.empty()) {
      EXPECT_NO_THROW(report_key(k.error_key)) << k.key;
    }
    EXPECT_EQ(k.sweep_page.header.empty(), k.sweep_page.format.empty()) << k.key;
    if (k.convention) {
      EXPECT_FALSE(k.help.empty()) << k.key;  // report.json's conventions
    }
  }
  for (std::string_view key : sweep_leading_columns()) EXPECT_NO_THROW(report_key(key)) << key;
  for (const FamiliesColumn& c : families_table_columns())
    EXPECT_NO_THROW(report_key(c.key)) << c.key;
  EXPECT_THROW(report_key("no_such_key"), std::logic_error);
}

TEST(ReportSchema, PageRowsComeFirstInThePagesOrder) {
  bool page = true;
  for (const ReportKey& k : report_key_table()) {
    if (k.page == PageTable::kNone) page = false;
    EXPECT_TRUE(page || k.page == PageTable::kNone) << k.key << " after a key not on the page";
  }
  EXPECT_EQ(report_key_table().front().key, "surface");
}

TEST(ReportSchema, TimingKeysAreTheClocksAndCounters) {
  const std::vector<std::string> t = timing_report_keys();
  const std::set<std::string> timing(t.begin(), t.end());
  // The ones the resume tests have always ignored.
  for (const char* key :
       {"wall_seconds", "solver_seconds", "measure_seconds", "quality_seconds", "volume_seconds",
        "seconds_per_vcycle", "preview_seconds", "page_seconds", "write_seconds",
        "surface_mesh_seconds", "checkpoint_seconds", "peak_memory_bytes",
        "peak_memory_bytes_per_cell", "checkpoints_written", "resumed_from_step"})
    EXPECT_TRUE(timing.count(key)) << key;
  for (const char* key : {"area", "steps", "vcycles", "mean_curvature", "converged"})
    EXPECT_FALSE(timing.count(key)) << key;
}

TEST(ReportSchema, NumbersAreFormattedAsTheTablesAlwaysWereWritten) {
  EXPECT_EQ(format_report_number("{:+.3%}", 0.003123133035079162), "+0.312%");
  EXPECT_EQ(format_report_number("{:+.4%}", 4.3647859912399056e-05), "+0.0044%");
  EXPECT_EQ(format_report_number("{:.3g}", 3.197224069037266), "3.2");
  EXPECT_EQ(summary_number("area", 3.0836526295383719), "3.083653");
  EXPECT_EQ(member_line_number("mean_curvature", 0.24772959099616076), "+0.2477");
  EXPECT_EQ(member_line_number("steps", 30.0), "30");
}

TEST(ReportSchema, HistoryColumnsAndStages) {
  EXPECT_EQ(history_header(),
            "step,stage,time,area,d_area,d_phi,energy,mass,vcycles,residual,elapsed,dt,"
            "volume_fraction,equilibrium_residual");
  int i = 0;
  for (const HistoryColumnInfo& c : history_column_table()) EXPECT_EQ(int(c.id), i++) << c.name;
  for (RunStage s : {RunStage::kPrerelax, RunStage::kRelax, RunStage::kVolume})
    EXPECT_EQ(parse_run_stage(run_stage_name(s)), s);
  EXPECT_EQ(run_stage_name(RunStage::kPrerelax), "prerelax");
  EXPECT_FALSE(parse_run_stage("relax@32"));
  EXPECT_FALSE(parse_run_stage(""));
}

TEST(ReportSchema, DumpHoldsEveryTable) {
  const nlohmann::json j = nlohmann::json::parse(report_schema_json());
  ASSERT_EQ(j.at("report_keys").size(), report_key_table().size());
  std::vector<std::string> timing;
  for (const nlohmann::json& k : j["report_keys"])
    if (k.at("timing").get<bool>()) timing.push_back(k.at("key"));
  std::sort(timing.begin(), timing.end());
  EXPECT_EQ(timing, timing_report_keys());
  EXPECT_EQ(j.at("history_columns").size(), history_column_table().size());
  EXPECT_EQ(j.at("history_columns")[9].at("format"), "{:.6e}");
  EXPECT_EQ(j.at("sweep_leading_columns").size(), sweep_leading_columns().size());
  EXPECT_EQ(j.at("families_table")[0].at("header"), "alpha");
  EXPECT_EQ(j.at("stages"), nlohmann::json({"prerelax", "relax", "volume"}));
  ASSERT_EQ(j.at("nested_report_keys").size(), nested_report_key_table().size());
  EXPECT_EQ(j.at("nested_report_keys")[0].at("path"), "crystallographic_cell.space_group");
  ASSERT_EQ(j.at("sweep_json_keys").size(), sweep_json_key_table().size());
  EXPECT_EQ(j.at("sweep_json_keys")[0].at("path"), "members");
}

// The --properties stage's summary keys are generated entries: each quantity, its N/2 error
// where the stage computes one, and the nodal twin's (pipeline/properties_stage.cpp).
TEST(ReportSchema, PropertiesSummaryKeysAreDeclared) {
  for (const char* key : {"properties_youngs_modulus", "properties_youngs_modulus_error",
                          "properties_nodal_zener_ratio_error", "properties_specific_surface",
                          "properties_nodal_wall_shear_stress", "properties_ramp"})
    EXPECT_NO_THROW(report_key(key)) << key;
  EXPECT_THROW(report_key("properties_specific_surface_error"), std::logic_error);
  EXPECT_EQ(report_key("properties_nodal_permeability").unit, "cell size²");
  EXPECT_EQ(report_key("properties_nodal_youngs_modulus_error").label, "nodal E / E_s error");
}

// The path of the dictionary (or list of dictionaries: "x[]") that holds `path`; "" at the top.
std::string parent_of(std::string_view path) {
  const std::size_t dot = path.rfind('.');
  if (dot == std::string_view::npos) return "";
  std::string parent(path.substr(0, dot));
  if (parent.size() > 2 && parent.compare(parent.size() - 2, 2, "[]") == 0)
    parent.resize(parent.size() - 2);
  return parent;
}

// Each nested key sits in a declared dictionary (its parent an entry of the same table, or for
// report.json a top-level key of report_key_table()), once, with a label and help, and `like`
// names a declared dictionary; the tables list what the report's writers write (checked on real
// reports by cli.report_reference).
TEST(ReportSchema, NestedKeysSitInDeclaredDictionaries) {
  for (const auto* table : {&nested_report_key_table(), &sweep_json_key_table()}) {
    const bool report = table == &nested_report_key_table();
    std::set<std::string> paths;
    for (const NestedKey& k : *table) {
      EXPECT_TRUE(paths.insert(std::string(k.path)).second) << k.path;
      EXPECT_FALSE(k.label.empty()) << k.path;
      EXPECT_FALSE(k.help.empty()) << k.path;
    }
    for (const NestedKey& k : *table) {
      const std::string parent = parent_of(k.path);
      if (parent.empty()) {
        EXPECT_FALSE(report) << k.path << ": a top-level key belongs in report_key_table()";
      } else if (report && parent.find('.') == std::string::npos) {
        EXPECT_NO_THROW(report_key(parent)) << k.path;
      } else {
        EXPECT_TRUE(paths.count(parent)) << k.path << ": its dictionary is not declared";
      }
      if (k.like.empty()) continue;
      if (report && k.like.find('.') == std::string_view::npos) {
        EXPECT_NO_THROW(report_key(k.like)) << k.path;  // a top-level dictionary
      } else {
        EXPECT_TRUE(paths.count(std::string(k.like))) << k.path;
      }
    }
  }
  // What the pages and Python read.
  for (const char* path : {"crystallographic_cell.computed_cell.area", "checkpoint.signal",
                           "properties.youngs_modulus", "properties.nodal",
                           "properties.solver.flow.preconditioner_shift"}) {
    const auto& t = nested_report_key_table();
    EXPECT_TRUE(std::any_of(t.begin(), t.end(), [&](const NestedKey& k) { return k.path == path; }))
        << path;
  }
}

}  // namespace
}  // namespace cmcsurf
