// The properties stage's pictures: the directional Young's modulus of an isotropic solid is one
// colour (a sphere, E = E_s everywhere), of a cubic one spans the scale; the designer's chart
// fits exact Gibson-Ashby data to its C and n and leaves out members without properties.
#include "pipeline/properties_pictures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "properties/cell_properties.h"

namespace cmcsurf {
namespace {

nlohmann::json stiffness_json(const properties::Matrix6& c) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& row : c) rows.push_back(std::vector<double>(row.begin(), row.end()));
  return {{"stiffness_voigt", rows}};
}

// Distinct colours among the saturated pixels (the surface; text and axes are grey).
std::set<int> surface_colours(const Image& img) {
  std::set<int> colours;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const std::uint8_t* p = img.pixel(x, y);
      const int spread = std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]});
      if (spread > 60) colours.insert((p[0] / 32) * 64 + (p[1] / 32) * 8 + p[2] / 32);
    }
  return colours;
}

TEST(PropertiesPictures, YoungsModulusOfIsotropicAndCubicSolids) {
  // Isotropic: every vertex at t = 1/2, the scale's light grey, so no saturated surface pixel
  // beyond the colour bar's.
  const auto iso = youngs_modulus_picture(
      stiffness_json(properties::isotropic_stiffness(0.3)), "isotropic");
  ASSERT_GT(iso.image.width, 500);
  EXPECT_GT(iso.seconds, 0.0);
  properties::Matrix6 c{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) c[i][j] = i == j ? 2.0 : 1.0;
    c[i + 3][i + 3] = 1.5;  // Zener ratio 3
  }
  const auto cubic = youngs_modulus_picture(stiffness_json(c), "cubic");
  ASSERT_EQ(cubic.image.width, iso.image.width);
  // The colour bar alone is in both; the cubic surface adds colours from blue to red.
  EXPECT_GT(surface_colours(cubic.image).size(), surface_colours(iso.image).size() + 5);
  EXPECT_TRUE(youngs_modulus_picture(nlohmann::json::object(), "none").image.rgb.empty());
}

TEST(PropertiesPictures, ChartFitsExactPowerLawsPerFamily) {
  std::vector<nlohmann::json> reports;
  for (const auto& [surface, c, n] : {std::tuple{"G", 0.19, 1.71}, std::tuple{"P", 0.3, 1.4}})
    for (double rho : {0.2, 0.3, 0.5}) {
      nlohmann::json r = {{"surface", surface},
                          {"properties", {{"solid", "network"}}},
                          {"properties_relative_density", rho},
                          {"properties_youngs_modulus", c * std::pow(rho, n)},
                          {"properties_youngs_modulus_error", 0.01 * c * std::pow(rho, n)},
                          {"properties_conductivity_solid", 0.5 * std::pow(rho, 1.2)},
                          {"properties_nodal_relative_density", rho},
                          {"properties_nodal_youngs_modulus", 2 * c * std::pow(rho, n)},
                          {"properties_nodal_conductivity_solid", std::pow(rho, 1.1)}};
      reports.push_back(r);
    }
  reports.push_back({{"surface", "D"}});  // a member without --properties: left out
  const PropertiesChart chart = properties_chart(reports, "test");
  ASSERT_FALSE(chart.image.rgb.empty());
  ASSERT_EQ(chart.fits.size(), 8u);  // 2 families x (CMC, nodal) x (E, k)
  for (const auto& f : chart.fits) {
    ASSERT_TRUE(f["valid"].get<bool>()) << f.dump();
    EXPECT_EQ(f["points"], 3);
    const bool g = f["surface"] == "G", cmc = f["part"] == "cmc";
    const double c = g ? 0.19 : 0.3, n = g ? 1.71 : 1.4;
    if (f["quantity"] == "youngs_modulus") {
      EXPECT_NEAR(f["exponent"].get<double>(), n, 1e-12);
      EXPECT_NEAR(f["coefficient"].get<double>(), (cmc ? 1 : 2) * c, 1e-12);
    } else {
      EXPECT_NEAR(f["exponent"].get<double>(), cmc ? 1.2 : 1.1, 1e-12);
      EXPECT_NEAR(f["coefficient"].get<double>(), cmc ? 0.5 : 1.0, 1e-12);
    }
  }
  // A bar per member that carries an error (CMC E only here), at its value, of its size.
  ASSERT_EQ(chart.error_bars.size(), 6u);
  for (const auto& b : chart.error_bars) {
    EXPECT_EQ(b["part"], "cmc");
    EXPECT_EQ(b["quantity"], "youngs_modulus");
    EXPECT_DOUBLE_EQ(b["error"].get<double>(), 0.01 * b["value"].get<double>());
  }
  EXPECT_TRUE(properties_chart({nlohmann::json{{"surface", "G"}}}, "none").image.rgb.empty());
}

// A member with a ramp of sheet porosities is one point per porosity (and its own top-level
// point is not drawn twice): three points on an exact law fit it exactly.
TEST(PropertiesPictures, ChartDrawsARampPerPorosity) {
  nlohmann::json ramp = nlohmann::json::array();
  for (double rho : {0.1, 0.3, 0.5})
    ramp.push_back({{"properties_porosity", 1 - rho},
                    {"properties_relative_density", rho},
                    {"properties_youngs_modulus", 0.6 * std::pow(rho, 1.3)},
                    {"properties_youngs_modulus_error", 0.001},
                    {"properties_conductivity_solid", 0.7 * rho}});
  nlohmann::json r = ramp[0];
  r["surface"] = "G";
  r["properties"] = {{"solid", "sheet"}};
  r["properties_ramp"] = ramp;
  const PropertiesChart chart = properties_chart({r}, "ramp");
  ASSERT_EQ(chart.fits.size(), 2u);
  for (const auto& f : chart.fits) {
    EXPECT_EQ(f["solid"], "sheet");
    EXPECT_EQ(f["points"], 3);
    const bool e = f["quantity"] == "youngs_modulus";
    EXPECT_NEAR(f["exponent"].get<double>(), e ? 1.3 : 1.0, 1e-12);
    EXPECT_NEAR(f["coefficient"].get<double>(), e ? 0.6 : 0.7, 1e-12);
  }
  EXPECT_EQ(chart.error_bars.size(), 3u);
}

// With permeabilities the chart gains the k-porosity panel (a third panel: wider) and each
// family and part a Kozeny-Carman constant: members on k = eps^3 / (c S^2) with the specific
// surface varying return that c to 1e-12, a scatter of e^(+-0.1) about it the geometric mean,
// and a bar per member carrying permeability_error.
TEST(PropertiesPictures, ChartFitsKozenyCarmanPerFamily) {
  std::vector<nlohmann::json> reports;
  const double scatter[] = {std::exp(0.1), std::exp(-0.1), 1.0};
  int i = 0;
  for (double rho : {0.1, 0.3, 0.5}) {
    const double eps = 1 - rho, surface = 2.0 + 3.0 * rho, c_cmc = 5.0, c_nodal = 7.0;
    reports.push_back({{"surface", "G"},
                       {"properties", {{"solid", "network"}}},
                       {"properties_relative_density", rho},
                       {"properties_youngs_modulus", 0.5 * rho * rho},
                       {"properties_permeability", std::pow(eps, 3) / (c_cmc * surface * surface)},
                       {"properties_permeability_error", 1e-4},
                       {"properties_specific_surface", surface},
                       {"properties_nodal_relative_density", rho},
                       {"properties_nodal_permeability",
                        scatter[i++] * std::pow(eps, 3) / (c_nodal * surface * surface)},
                       {"properties_nodal_specific_surface", surface}});
  }
  const PropertiesChart chart = properties_chart(reports, "flow");
  const PropertiesChart without = properties_chart(
      {nlohmann::json{{"surface", "G"},
                      {"properties", {{"solid", "network"}}},
                      {"properties_relative_density", 0.3},
                      {"properties_youngs_modulus", 0.05}}},
      "no flow");
  EXPECT_GT(chart.image.width, without.image.width + 400);
  int kc = 0;
  for (const auto& f : chart.fits) {
    if (f["quantity"] != "kozeny_carman_constant") continue;
    ++kc;
    ASSERT_TRUE(f["valid"].get<bool>());
    EXPECT_EQ(f["points"], 3);
    const bool cmc = f["part"] == "cmc";
    EXPECT_NEAR(f["coefficient"].get<double>(), cmc ? 5.0 : 7.0, 1e-12);
    // log c of the members: 0, -0.1, +0.1 about log 7 (k up by e^0.1 is c down by it).
    EXPECT_NEAR(f["rms_log_residual"].get<double>(), cmc ? 0.0 : std::sqrt(0.02 / 3), 1e-12);
  }
  EXPECT_EQ(kc, 2);
  int bars = 0;
  for (const auto& b : chart.error_bars)
    if (b["quantity"] == "permeability") {
      ++bars;
      EXPECT_EQ(b["part"], "cmc");
      EXPECT_EQ(b["error"], 1e-4);
    }
  EXPECT_EQ(bars, 3);
}

}  // namespace
}  // namespace cmcsurf
