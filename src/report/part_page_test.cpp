#include "report/part_page.h"

#include <gtest/gtest.h>

#include <regex>
#include <string>

namespace cmcsurf {
namespace {

int count(const std::string& s, const std::string& what) {
  int n = 0;
  for (auto at = s.find(what); at != std::string::npos; at = s.find(what, at + 1)) ++n;
  return n;
}

// Every data-path cell of the html: its pointer's number in the report, to all 17 digits
// (a band without nodes is null in FILE.json and shows a dash). Returns the cells checked.
int check_cells(const std::string& html, const nlohmann::json& report) {
  const std::regex cell("<td data-path=\"([^\"]+)\"(?: data-value=\"([^\"]+)\")?>");
  int n = 0;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), cell);
       it != std::sregex_iterator(); ++it, ++n) {
    const nlohmann::json& v = report[nlohmann::json::json_pointer((*it)[1].str())];
    if (v.is_number()) EXPECT_EQ(std::stod((*it)[2].str()), v.get<double>()) << (*it)[1];
    else EXPECT_FALSE((*it)[2].matched) << (*it)[1];
  }
  return n;
}

TEST(PartPage, GradedProfileByDepthShowsEveryBand) {
  // FILE.json's graded keys of a fill by depth: four bands over 1.5 mm and the core; the
  // third band has no nodes (its numbers null, as NaN is written).
  nlohmann::json report = {
      {"units", "mm"},
      {"graded",
       {{"by", "surface"}, {"axis", nullptr}, {"depth", 1.5}, {"porosity_from", 0.5},
        {"porosity_to", 0.7},
        {"profile",
         {{{"depth_from", 0.0}, {"depth_to", 0.375}, {"porosity_target", 0.525},
           {"porosity_nodes", 0.5312}},
          {{"depth_from", 0.375}, {"depth_to", 0.75}, {"porosity_target", 0.575},
           {"porosity_nodes", 0.5701}},
          {{"depth_from", 0.75}, {"depth_to", 1.125}, {"porosity_target", nullptr},
           {"porosity_nodes", nullptr}},
          {{"depth_from", 1.125}, {"depth_to", 1.5}, {"porosity_target", 0.675},
           {"porosity_nodes", 0.6633}},
          {{"depth_from", 1.5}, {"depth_to", nullptr}, {"porosity_target", 0.7},
           {"porosity_nodes", 0.7049}}}}}},
      {"morphometry",
       {{"members",
         {{{"porosity", 0.7}, {"wall_thickness", {{"mean", 0.31}, {"min", 0.12}}},
           {"pore_size", {{"mean", 0.52}, {"min", 0.2}}}},
          {{"porosity", 0.5}, {"wall_thickness", {{"mean", 0.41}, {"min", 0.15}}},
           {"pore_size", {{"mean", 0.44}, {"min", 0.18}}}}}}}}};
  const std::string html = graded_profile_html(report);
  EXPECT_NE(html.find("data-title=\"porosity profile\" data-bands=\"5\" data-drawn=\"4\""),
            std::string::npos);
  EXPECT_EQ(count(html, "<circle"), 4);  // measured: the bands with nodes
  // The target's line: one move and a segment to each further band with a target.
  const std::smatch line = [&] {
    std::smatch m;
    std::regex_search(html, m, std::regex("<path d=\"(M[^\"]*)\" stroke=\"#2b5cd6\""));
    return m;
  }();
  ASSERT_FALSE(line.empty());
  EXPECT_EQ(count(line[1].str(), "L"), 3);
  EXPECT_NE(html.find("depth below the surface (mm); last: the core"), std::string::npos);
  EXPECT_NE(html.find("<th>1.5 – core</th>"), std::string::npos);
  // 5 bands x (target, measured) + 2 members x (porosity, wall mean, min, pore mean, min).
  EXPECT_EQ(check_cells(html, report), 10 + 10);
  EXPECT_EQ(count(html, "<td data-path=\"/graded/profile/2/"), 2);
  EXPECT_EQ(count(html, "data-value"), 18);  // band 2's two cells are dashes
}

TEST(PartPage, GradedProfileAlongAnAxisAndUngraded) {
  nlohmann::json report = {
      {"units", "mm"},
      {"graded",
       {{"by", "axis"}, {"axis", "z"},
        {"profile",
         {{{"from", 0.0}, {"to", 2.0}, {"porosity_target", 0.55}, {"porosity_nodes", 0.56}},
          {{"from", 2.0}, {"to", 4.0}, {"porosity_target", 0.65}, {"porosity_nodes", 0.64}}}}}}};
  const std::string html = graded_profile_html(report);
  EXPECT_NE(html.find("<h2>Porosity along z: target and measured</h2>"), std::string::npos);
  EXPECT_NE(html.find("position along z (mm)"), std::string::npos);
  EXPECT_NE(html.find("<th>2 – 4</th>"), std::string::npos);
  EXPECT_EQ(check_cells(html, report), 4);
  EXPECT_EQ(html.find("id=\"members\""), std::string::npos);  // no members: no table
  // A graded cell size: its profile at one porosity, along its axis.
  nlohmann::json cells = {{"units", "mm"}, {"graded_cell_size", report["graded"]}};
  cells["graded_cell_size"].erase("by");
  EXPECT_NE(graded_profile_html(cells).find("Porosity along z"), std::string::npos);
  // An ungraded part has no such section.
  EXPECT_EQ(graded_profile_html({{"units", "mm"}, {"porosity", 0.7}}), "");
}

}  // namespace
}  // namespace cmcsurf
