// report.html (docs/report.md): one self-contained page, with its script (three.js and
// web/src/page.js, compiled into the binary) and its data inlined, so it opens from a file with
// no network. The page draws what is given here; every number on it is formatted here.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/text_encoding.h"  // base64, html_escape: the page's encoders
#include "render/draw_surface.h"
#include "render/preview.h"

namespace cmcsurf {

// A mesh for the page: counts, the cell origin o, and base64 of little-endian arrays: positions
// as uint16 q with x = o + q / 65535 (the cell spans [o, o + 1]), int8 normals (x127), float32
// curvature, and triangle indices as uint16 (index_bytes 2, up to 65536 vertices) or uint32.
nlohmann::json mesh_json(const DrawSurface& s);

// The colour scale and the colour table (render/colormap.h) the page colours with.
nlohmann::json color_scale_json(const ColorScale& scale);

// A row of a numbers table: a report key, its label, and how to format it.
struct NumberRow {
  std::string key;
  std::string label;
  std::string format = "{:.6g}";  // fmt format of a number
  std::string error_key;          // shown as "+- error" if the report has it
};
// The key numbers of a run, in the page's order.
const std::vector<NumberRow>& run_number_rows();

// x in a NumberRow's format; "{:+.4%}" prints 100 x with a percent sign.
std::string format_number(const std::string& format, double x);

// <table> of the rows present in `report`: each value cell carries data-key and, for numbers,
// data-value with all 17 digits, so a test can compare the page with report.json.
std::string numbers_table_html(const nlohmann::json& report, const std::vector<NumberRow>& rows,
                               const std::string& id);

// The properties section of a run page: report.json's `properties` (docs/properties.md) as a
// table, one row per number (stiffness, conductivities, fractions of the Hashin-Shtrikman
// bounds), one column per solid (CMC, and the nodal twins when present). Each value cell carries
// data-path, the JSON pointer of its number in report.json, and data-value with all 17 digits;
// "± e" where the dictionary has the grid check's *_error.
std::string properties_table_html(const nlohmann::json& properties);

struct ReportPage {
  std::string title;     // <title> and <h1>
  std::string subtitle;  // under the title
  std::string body;      // HTML sections after the 3D view (already escaped)
  nlohmann::json data;   // what page.js draws (kind "run" or "sweep")
};
std::string report_page_html(const ReportPage& page);

}  // namespace cmcsurf
