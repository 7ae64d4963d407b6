// The pictures of the properties stage (docs/properties.md), drawn with render/: the
// directional Young's modulus surface of one solid (youngs_modulus.png in a run folder,
// FILE-youngs.png beside `cmcsurf properties`' FILE.json) and a sweep's designer's chart
// (properties_chart.png: E/E_s and k/k_s against relative density, log-log, per family, with
// the fitted Gibson-Ashby law C rho^n).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/image.h"

namespace cmcsurf {

inline constexpr const char* kYoungsPictureName = "youngs_modulus.png";  // in a run folder
inline constexpr const char* kPropertiesChartName = "properties_chart.png";  // in a sweep folder

struct PropertiesPicture {
  Image image;           // empty: the dictionary has no stiffness (--only conductivity)
  double seconds = 0.0;  // the stage's wall time (the surface and its drawing)
};

// E(d) = 1 / (d d : S : d d) of a properties dictionary's stiffness_voigt as the surface
// r = E(d) d, coloured by E (blue at the minimum, red at the maximum), with the axes, a colour
// bar and the extremes with their directions.
PropertiesPicture youngs_modulus_picture(const nlohmann::json& properties,
                                         const std::string& title);

struct PropertiesChart {
  Image image;
  // One object per family, solid, part (cmc, nodal) and quantity (youngs_modulus,
  // conductivity_solid): surface, solid, part, quantity, coefficient C, exponent n,
  // rms_log_residual, points, valid.
  nlohmann::json fits = nlohmann::json::array();
  // One object per bar drawn (a member's properties_*_error > 0): surface, solid, part,
  // quantity, relative_density, value, error.
  nlohmann::json error_bars = nlohmann::json::array();
  double seconds = 0.0;
};

// The chart of a sweep's member reports (report.json with properties and properties_*; those
// without are left out): E/E_s and k_s against properties_relative_density on log-log axes,
// one colour per family, CMC solid lines, nodal (properties_nodal_*) dashed, the
// Hashin-Shtrikman upper bound dotted, error bars from properties_*_error, each fit's C and n
// in the legend. Empty image (and no fits) when no member has properties.
PropertiesChart properties_chart(const std::vector<nlohmann::json>& reports,
                                 const std::string& title);

}  // namespace cmcsurf
