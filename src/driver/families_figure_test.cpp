#include "driver/families_figure.h"

#include <gtest/gtest.h>

#include <cmath>

namespace cmcsurf {
namespace {

// Three members of one family with known values and error bars (the diffuse ones 2 % low).
std::vector<nlohmann::json> family(const char* surface) {
  std::vector<nlohmann::json> reports;
  for (double a : {0.4, 0.5, 0.6}) {
    const double area = 3.0 - 4.0 * (a - 0.5) * (a - 0.5), h = 5.0 * (0.5 - a);
    reports.push_back({{"surface", surface},
                       {"volume_fraction_target", a},
                       {"area", area},
                       {"area_error", 0.02},
                       {"mean_curvature", h},
                       {"mean_curvature_error", 0.05},
                       {"area_diffuse", 0.98 * area},
                       {"mean_curvature_diffuse", h + 0.1}});
  }
  return reports;
}

// The first family's colour (a blue) at pixel (x, y), rounded down to the pixel it covers.
bool family_colour(const Image& img, double x, double y) {
  const std::uint8_t* p = img.pixel(int(std::floor(x)), int(std::floor(y)));
  return p[2] > 120 && p[2] > p[0] + 40;
}

TEST(FamiliesFigure, DrawsTheSharpPointsWithTheirErrorBars) {
  const FamiliesFigure f = families_figure(family("G"), {});
  ASSERT_FALSE(f.image.rgb.empty());
  ASSERT_EQ(f.points.size(), 3u);
  std::size_t inked = 0;
  for (std::size_t i = 0; i < f.image.rgb.size(); i += 3)
    inked += f.image.rgb[i] < 200 || f.image.rgb[i + 1] < 200 || f.image.rgb[i + 2] < 200;
  EXPECT_GT(inked, 5000u);  // axes, text, three points: not blank
  // Pixels per unit of area from the markers of 0.4 (2.96) and 0.5 (3.0).
  const nlohmann::json &p0 = f.points[0], &p1 = f.points[1];
  const double scale = (p0["y_area"].get<double>() - p1["y_area"].get<double>()) / 0.04;
  ASSERT_GT(scale, 100.0);
  for (const nlohmann::json& p : f.points) {
    for (const char* panel : {"area", "mean_curvature"}) {
      const double x = p[std::string(panel) == "area" ? "x_area" : "x"].get<double>();
      const double y = p[std::string("y_") + panel].get<double>();
      const double top = p[std::string("y_") + panel + "_bar"][0].get<double>();
      const double bottom = p[std::string("y_") + panel + "_bar"][1].get<double>();
      EXPECT_TRUE(family_colour(f.image, x, y)) << panel << " marker at " << p.dump();
      // The bar: +-error about the marker, drawn between the marker and its ends, and nothing
      // of the family's colour beyond its caps.
      EXPECT_NEAR(y - top, bottom - y, 1e-9);
      EXPECT_TRUE(family_colour(f.image, x, (y + top) / 2 - 3)) << panel;
      EXPECT_TRUE(family_colour(f.image, x, (y + bottom) / 2 + 3)) << panel;
      EXPECT_FALSE(family_colour(f.image, x, top - 6)) << panel;
      EXPECT_FALSE(family_colour(f.image, x, bottom + 6)) << panel;
    }
    EXPECT_NEAR(p["y_area_bar"][1].get<double>() - p["y_area_bar"][0].get<double>(),
                2 * 0.02 * scale, 1e-6);
  }
}

// The diffuse layer's values appear only when asked for: its ring 2 % below the sharp area
// (about 70 pixels down here, outside the error bar) is inked then and blank otherwise.
TEST(FamiliesFigure, DiffuseValuesOnlyOnRequest) {
  const std::vector<nlohmann::json> reports = family("G");
  const FamiliesFigure plain = families_figure(reports, {});
  const FamiliesFigure diffuse = families_figure(reports, {.title = "", .diffuse = true});
  ASSERT_FALSE(plain.image.rgb.empty());
  ASSERT_FALSE(diffuse.image.rgb.empty());
  // The ring of radius 3 around the diffuse area of the middle member, in the second figure's
  // frame (its range includes the diffuse values); the first figure has nothing there.
  const nlohmann::json& p = diffuse.points[1];
  const double scale = (diffuse.points[0]["y_area"].get<double>() - p["y_area"].get<double>()) /
                       0.04;
  const double x = p["x_area"].get<double>();
  const double y_ring = p["y_area"].get<double>() + 0.02 * 3.0 * scale;
  EXPECT_TRUE(family_colour(diffuse.image, x + 3, y_ring));
  const nlohmann::json& q = plain.points[1];
  const double plain_scale =
      (plain.points[0]["y_area"].get<double>() - q["y_area"].get<double>()) / 0.04;
  EXPECT_FALSE(family_colour(plain.image, q["x_area"].get<double>() + 3,
                             q["y_area"].get<double>() + 0.02 * 3.0 * plain_scale));
}

TEST(FamiliesFigure, NoSharpValuesNoFigure) {
  const FamiliesFigure f =
      families_figure({{{"surface", "G"}, {"volume_fraction_target", 0.5}}}, {});
  EXPECT_TRUE(f.image.rgb.empty());
  EXPECT_TRUE(f.points.empty());
}

TEST(FamiliesFigure, LiteratureComesFromMeasure) {
  const nlohmann::json j = literature_json();
  EXPECT_EQ(j["minimal_surface_areas"]["G"]["area"], 3.0915);
  EXPECT_EQ(j["i_scp"]["area"][49], 2.0);  // alpha = 0.5: the plane pair
}

}  // namespace
}  // namespace cmcsurf
