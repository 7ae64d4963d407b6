#include "report/report_html.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "render/assets.h"
#include "render/colormap.h"
#include "schema/report_schema.h"

namespace cmcsurf {

static_assert(std::endian::native == std::endian::little, "the page reads little-endian arrays");

namespace {

template <class T>
std::string_view as_bytes(const std::vector<T>& v) {
  return {reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T)};
}

}  // namespace

nlohmann::json mesh_json(const DrawSurface& s) {
  std::vector<std::uint16_t> positions(s.positions.size() * 3);
  for (std::size_t i = 0; i < s.positions.size(); ++i)
    for (int a = 0; a < 3; ++a)
      positions[3 * i + a] = std::uint16_t(
          std::lround(std::clamp((s.positions[i][a] - s.origin) * 65535.0f, 0.0f, 65535.0f)));
  std::vector<std::int8_t> normals(s.normals.size() * 3);
  for (std::size_t i = 0; i < s.normals.size(); ++i)
    for (int a = 0; a < 3; ++a)
      normals[3 * i + a] = std::int8_t(std::lround(127.0f * s.normals[i][a]));
  nlohmann::json out = {{"vertices", s.positions.size()},
                        {"triangles", s.triangles.size()},
                        {"origin", s.origin},
                        {"positions", base64(as_bytes(positions))},
                        {"normals", base64(as_bytes(normals))},
                        {"curvature", base64(as_bytes(s.curvature))}};
  if (s.positions.size() <= 65536) {
    std::vector<std::uint16_t> indices(s.triangles.size() * 3);
    for (std::size_t t = 0; t < s.triangles.size(); ++t)
      for (int c = 0; c < 3; ++c) indices[3 * t + c] = std::uint16_t(s.triangles[t][c]);
    out["index_bytes"] = 2;
    out["indices"] = base64(as_bytes(indices));
  } else {
    out["index_bytes"] = 4;
    out["indices"] = base64(as_bytes(s.triangles));
  }
  return out;
}

nlohmann::json color_scale_json(const ColorScale& scale) {
  nlohmann::json stops = nlohmann::json::array();
  for (const ColorStop& s : diverging_stops())
    stops.push_back({s.t, s.color.r, s.color.g, s.color.b});
  return {{"centre", scale.centre}, {"half_range", scale.half_range}, {"stops", stops}};
}

const std::vector<NumberRow>& run_number_rows() {
  static const std::vector<NumberRow> rows = [] {
    std::vector<NumberRow> out;
    for (const ReportKey& k : report_key_table())
      if (k.page == PageTable::kKeyNumbers)
        out.push_back({std::string(k.key), std::string(k.label), std::string(k.format),
                       std::string(k.error_key)});
    return out;
  }();
  return rows;
}

namespace {

struct PropertyRow {
  const char* pointer;  // within one solid's dictionary
  const char* label;
  const char* format;   // "" for a direction (three numbers)
};

// What a designer compares (docs/properties.md names the keys), in the page's order.
constexpr PropertyRow kPropertyRows[] = {
    {"/relative_density", "solid fraction ρ (relative density)", "{:.5f}"},
    {"/porosity", "porosity", "{:.5f}"},
    {"/thickness", "sheet thickness", "{:.5g}"},
    {"/youngs_modulus/0", "Young's modulus E_x / E_s", "{:.5g}"},
    {"/youngs_modulus/1", "Young's modulus E_y / E_s", "{:.5g}"},
    {"/youngs_modulus/2", "Young's modulus E_z / E_s", "{:.5g}"},
    {"/youngs_modulus_gpa/0", "Young's modulus E_x (GPa)", "{:.5g}"},
    {"/shear_modulus/0", "shear modulus G_yz / E_s", "{:.5g}"},
    {"/shear_modulus/1", "shear modulus G_xz / E_s", "{:.5g}"},
    {"/shear_modulus/2", "shear modulus G_xy / E_s", "{:.5g}"},
    {"/poisson_ratio/0", "Poisson ratio ν_xy", "{:.4f}"},
    {"/poisson_ratio/1", "Poisson ratio ν_yz", "{:.4f}"},
    {"/poisson_ratio/2", "Poisson ratio ν_zx", "{:.4f}"},
    {"/bulk_modulus", "bulk modulus K / E_s", "{:.5g}"},
    {"/zener_ratio", "Zener ratio 2 C44 / (C11 − C12)", "{:.4g}"},
    {"/youngs_modulus_min", "E min / E_s", "{:.5g}"},
    {"/youngs_modulus_min_direction", "E min along", ""},
    {"/youngs_modulus_max", "E max / E_s", "{:.5g}"},
    {"/youngs_modulus_max_direction", "E max along", ""},
    {"/conductivity_solid/0/0", "conductivity of the solid k_xx / k_s", "{:.5g}"},
    {"/conductivity_solid/1/1", "conductivity of the solid k_yy / k_s", "{:.5g}"},
    {"/conductivity_solid/2/2", "conductivity of the solid k_zz / k_s", "{:.5g}"},
    {"/conductivity_pore/0/0", "conductivity of the pores k_xx / k_f", "{:.5g}"},
    {"/conductivity_pore/1/1", "conductivity of the pores k_yy / k_f", "{:.5g}"},
    {"/conductivity_pore/2/2", "conductivity of the pores k_zz / k_f", "{:.5g}"},
    {"/tortuosity_pore/0", "pore tortuosity (x)", "{:.4g}"},
    {"/fraction_of_bound/bulk_modulus", "K / Hashin-Shtrikman upper bound", "{:.4f}"},
    {"/fraction_of_bound/shear_modulus", "mean G / HS upper bound", "{:.4f}"},
    {"/fraction_of_bound/youngs_modulus", "mean E / HS upper bound", "{:.4f}"},
    {"/fraction_of_bound/conductivity_solid", "k solid / HS upper bound", "{:.4f}"},
    {"/fraction_of_bound/conductivity_pore", "k pores / HS upper bound", "{:.4f}"},
    {"/permeability/0/0", "permeability k_xx / cell size²", "{:.5g}"},
    {"/permeability/1/1", "permeability k_yy / cell size²", "{:.5g}"},
    {"/permeability/2/2", "permeability k_zz / cell size²", "{:.5g}"},
    {"/permeability_m2/0/0", "permeability k_xx (m²)", "{:.4g}"},
    {"/permeability_m2/1/1", "permeability k_yy (m²)", "{:.4g}"},
    {"/permeability_m2/2/2", "permeability k_zz (m²)", "{:.4g}"},
    {"/hydraulic_tortuosity/0", "hydraulic tortuosity (x)", "{:.4g}"},
    {"/specific_surface", "specific surface S × cell size", "{:.4g}"},
    {"/kozeny_carman_constant", "Kozeny-Carman constant ε³ / (k S²)", "{:.4g}"},
    {"/closed_pore_fraction", "closed pore fraction", "{:.4g}"},
    {"/wall_shear_stress_axis_mean/mean", "wall shear stress mean / (μ U / L), axes' mean",
     "{:.4g}"},
    {"/wall_shear_stress_axis_mean/p95", "wall shear stress p95 / (μ U / L), axes' mean",
     "{:.4g}"},
    {"/wall_shear_stress_mpa_axis_mean/mean", "wall shear stress mean (mPa), axes' mean",
     "{:.4g}"},
    {"/wall_shear_stress_mpa_axis_mean/median", "wall shear stress median (mPa), axes' mean",
     "{:.4g}"},
    {"/wall_shear_stress_mpa_axis_mean/p95", "wall shear stress p95 (mPa), axes' mean",
     "{:.4g}"},
    {"/pressure_drop_pa_per_m", "pressure drop along z (Pa/m)", "{:.4g}"},
};

// /key/i... -> /key_error/i... (the grid check's estimate of the same number).
std::string error_pointer(const std::string& pointer) {
  const std::size_t slash = pointer.find('/', 1);
  return slash == std::string::npos ? pointer + "_error"
                                    : pointer.substr(0, slash) + "_error" + pointer.substr(slash);
}

}  // namespace

std::string properties_table_html(const nlohmann::json& properties) {
  std::vector<std::pair<std::string, std::string>> sides = {{"CMC", ""}};
  if (properties.contains("nodal")) sides.push_back({"nodal", "/nodal"});
  if (properties.contains("nodal_offset")) sides.push_back({"nodal offset", "/nodal_offset"});
  std::string out = "<table class=\"numbers\" id=\"properties\">\n<tr><th></th>";
  for (const auto& s : sides) out += "<th>" + html_escape(s.first) + "</th>";
  out += "</tr>\n";
  for (const PropertyRow& row : kPropertyRows) {
    std::string cells;
    bool any = false;
    for (const auto& [name, prefix] : sides) {
      const nlohmann::json::json_pointer at(prefix + row.pointer);
      const std::string path = "/properties" + prefix + row.pointer;
      if (!properties.contains(at)) {
        cells += fmt::format("<td data-path=\"{}\">–</td>", html_escape(path));
        continue;
      }
      any = true;
      const nlohmann::json& v = properties[at];
      if (std::string(row.format).empty() && v.is_array() && v.size() == 3) {
        // E(d) = E(-d): the sign that makes the largest component positive, and no "-0.000".
        double d[3] = {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
        const int big = std::abs(d[0]) >= std::abs(d[1]) && std::abs(d[0]) >= std::abs(d[2])
                            ? 0
                            : (std::abs(d[1]) >= std::abs(d[2]) ? 1 : 2);
        const double sign = d[big] < 0 ? -1.0 : 1.0;
        for (double& x : d) x = std::abs(x) < 5e-4 ? 0.0 : sign * x;
        cells += fmt::format("<td data-path=\"{}\">[{:.3f} {:.3f} {:.3f}]</td>", html_escape(path),
                             d[0], d[1], d[2]);
        continue;
      }
      if (!v.is_number()) {
        cells += fmt::format("<td data-path=\"{}\">–</td>", html_escape(path));
        continue;
      }
      std::string text = format_number(row.format, v.get<double>());
      const nlohmann::json::json_pointer error(prefix + error_pointer(row.pointer));
      if (properties.contains(error) && properties[error].is_number())
        text += fmt::format(" ± {:.1e}", properties[error].get<double>());
      cells += fmt::format("<td data-path=\"{}\" data-value=\"{:.17g}\">{}</td>",
                           html_escape(path), v.get<double>(), html_escape(text));
    }
    if (any) out += fmt::format("<tr><th>{}</th>{}</tr>\n", html_escape(row.label), cells);
  }
  return out + "</table>\n";
}

std::string format_number(const std::string& format, double x) {
  return format_report_number(format, x);
}

std::string numbers_table_html(const nlohmann::json& report, const std::vector<NumberRow>& rows,
                               const std::string& id) {
  std::string out = fmt::format("<table class=\"numbers\" id=\"{}\">\n", html_escape(id));
  for (const NumberRow& row : rows) {
    if (!report.contains(row.key)) continue;
    const nlohmann::json& v = report[row.key];
    std::string cell;
    if (v.is_number()) {
      const double x = v.get<double>();
      std::string text = v.is_number_integer() ? fmt::format("{}", v.get<long long>())
                                               : format_number(row.format, x);
      if (!row.error_key.empty() && report.contains(row.error_key) &&
          report[row.error_key].is_number())
        text += fmt::format(" ± {:.1e}", report[row.error_key].get<double>());
      cell = fmt::format("<td data-key=\"{}\" data-value=\"{}\">{}</td>", html_escape(row.key),
                         v.is_number_integer() ? fmt::format("{}", v.get<long long>())
                                               : fmt::format("{:.17g}", x),
                         html_escape(text));
    } else if (v.is_null()) {
      cell = fmt::format("<td data-key=\"{}\">–</td>", html_escape(row.key));
    } else {
      const std::string text = v.is_string() ? v.get<std::string>() : v.dump();
      cell = fmt::format("<td data-key=\"{}\">{}</td>", html_escape(row.key), html_escape(text));
    }
    out += fmt::format("<tr><th>{}</th>{}</tr>\n", html_escape(row.label), cell);
  }
  return out + "</table>\n";
}

namespace {

// Text inside <script>: "</script" (any case) and "<!--" would end or confuse the element. In
// JSON '<' occurs only inside strings, where \u003c reads back the same; in the script bundle
// "<\/" and "<\!" read back the same inside strings and regular expressions.
std::string json_in_script(const nlohmann::json& data) {
  std::string out;
  for (char c : data.dump()) {
    if (c == '<')
      out += "\\u003c";
    else
      out += c;
  }
  return out;
}

std::string js_in_script(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    out += s[i];
    if (s[i] == '<' && i + 1 < s.size() && (s[i + 1] == '/' || s[i + 1] == '!')) out += '\\';
  }
  return out;
}

constexpr const char* kStyle = R"(
body { font: 15px/1.45 "DejaVu Sans", system-ui, sans-serif; margin: 0 auto; max-width: 1180px;
       padding: 12px 20px 40px; color: #1b1b1f; }
h1 { font-size: 24px; margin: 10px 0 2px; } h2 { font-size: 18px; margin: 26px 0 8px; }
.sub { color: #555; margin: 0 0 12px; }
#status { font-size: 12px; color: #777; }
#status.error { color: #b00; font-weight: bold; }
.viewer { display: flex; gap: 16px; align-items: flex-start; flex-wrap: wrap; }
#view { width: 760px; height: 560px; border: 1px solid #ccc; background: #fff; cursor: grab; }
.controls { min-width: 220px; }
.controls label { display: block; margin: 4px 0; }
.controls .bar { width: 28px; height: 260px; border: 1px solid #888; display: inline-block; }
.ticks { display: inline-block; vertical-align: top; height: 262px; position: relative;
         margin-left: 6px; width: 90px; }
.ticks span { position: absolute; font-size: 12px; transform: translateY(-50%); }
table.numbers { border-collapse: collapse; }
table.numbers th { text-align: left; font-weight: normal; color: #444; padding: 2px 16px 2px 0; }
table.numbers td { font-family: "DejaVu Sans Mono", monospace; padding: 2px 0; }
table.members { border-collapse: collapse; font-size: 13px; }
table.members td, table.members th { padding: 2px 8px; border-bottom: 1px solid #eee;
                                     text-align: right; }
table.members tr.member { cursor: pointer; } table.members tr.selected { background: #eef3ff; }
.charts { display: flex; flex-wrap: wrap; gap: 18px; }
svg text { font-size: 11px; fill: #333; }
img.plot { max-width: 100%; border: 1px solid #eee; }
)";

}  // namespace

std::string report_page_html(const ReportPage& page) {
  std::string out = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  out += fmt::format("<title>{}</title>\n<style>{}</style>\n</head>\n<body>\n",
                     html_escape(page.title), kStyle);
  out += fmt::format("<h1>{}</h1>\n<p class=\"sub\">{}</p>\n", html_escape(page.title),
                     html_escape(page.subtitle));
  out += "<div id=\"status\" data-status=\"loading\">loading the 3D view…</div>\n";
  out += "<section class=\"viewer\"><canvas id=\"view\"></canvas><div class=\"controls\" "
         "id=\"controls\"></div></section>\n";
  out += page.body;
  out += "<script type=\"application/json\" id=\"cmc-data\">" + json_in_script(page.data) +
         "</script>\n";
  if (report_page_has_viewer())
    out += "<script>" + js_in_script(report_page_js()) + "</script>\n";
  else
    out += "<script>document.getElementById('status').textContent = 'This cmcsurf was built "
           "without npm, so its pages have no 3D view (docs/report.md).';</script>\n";
  out += "</body>\n</html>\n";
  return out;
}

}  // namespace cmcsurf
