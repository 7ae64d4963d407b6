// families.png of a sweep (Fig. 11 of the paper), drawn with render/ from the members'
// reports: (a) the mean curvature H and (b) the area A against the volume fraction, one colour
// per family, the sharp values (report keys `mean_curvature`, `area`) as markers with their
// error bars (`mean_curvature_error`, `area_error`: the Richardson estimates), the literature
// areas of the minimal surfaces and the I_scp profile (measure/literature.h), the cell the
// numbers are per named on the axes and, for a family with a crystallographic cell
// (`crystallographic_cell`), how its numbers convert. The diffuse layer's values
// (`area_diffuse`, `mean_curvature_diffuse`) only when asked for.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/image.h"

namespace cmcsurf {

inline constexpr const char* kFamiliesFigureName = "families.png";  // in a sweep folder
inline constexpr const char* kFamiliesSvgName = "families.svg";     // the same, in an SVG

struct FamiliesFigureOptions {
  std::string title;
  bool diffuse = false;  // also the diffuse layer's H and A (dotted, same colour)
};

struct FamiliesFigure {
  Image image;  // empty: no report has a sharp area and H
  // One object per member drawn: surface, volume_fraction, area, area_error, mean_curvature,
  // mean_curvature_error, and where its marker and bar ends are in the image: x, y_area,
  // y_area_bar [top, bottom], y_mean_curvature, y_mean_curvature_bar (pixels).
  nlohmann::json points = nlohmann::json::array();
  double seconds = 0.0;
};

FamiliesFigure families_figure(const std::vector<nlohmann::json>& reports,
                               const FamiliesFigureOptions& options);

// families.svg: the figure's PNG in an SVG of its size (for pages and editors that take SVG).
std::string families_svg(const Image& image);

// Draws families.png and writes it with families.svg into a sweep folder (the title names the
// folder); returns sweep.json's "families_figure" entry (file, seconds, diffuse, points), or
// null when no report has a sharp area and H.
nlohmann::json write_families_figure(const std::filesystem::path& dir,
                                     const std::vector<nlohmann::json>& reports, bool diffuse);

// sweep.json's "literature": the constants the figure draws (measure/literature.h) as data,
// for scripts (scripts/plot_families.py) to draw the same.
nlohmann::json literature_json();

}  // namespace cmcsurf
