#include "io/run_report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

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

}  // namespace
}  // namespace cmcsurf
