#include "report/part_page.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "common/wall_clock.h"
#include "common/atomic_file.h"
#include "io/png.h"
#include "report/report_html.h"
#include "mesh/edge_collapse.h"
#include "mesh/shape.h"
#include "mesh/writers.h"
#include "render/preview.h"
#include "render/text.h"

namespace cmcsurf {

namespace fs = std::filesystem;

namespace {

// Where the plane x[axis] = at crosses the mesh: one segment per triangle it cuts.
PartSlice slice_mesh(const TriMesh& m, const MeshStats& box, int axis, double fraction) {
  PartSlice s;
  s.axis = axis;
  s.at = box.min[axis] + fraction * (box.max[axis] - box.min[axis]);
  s.plane_axes = {axis == 0 ? 1 : 0, axis == 2 ? 1 : 2};
  for (int c = 0; c < 2; ++c)
    s.lo[c] = box.min[s.plane_axes[c]], s.hi[c] = box.max[s.plane_axes[c]];
  for (const auto& t : m.triangles) {
    double d[3];
    for (int c = 0; c < 3; ++c) d[c] = m.vertices[t[c]][axis] - s.at;
    double pts[2][2];
    int n = 0;
    for (int c = 0; c < 3 && n < 2; ++c) {
      const int e = (c + 1) % 3;
      if ((d[c] > 0) == (d[e] > 0)) continue;
      const double w = d[c] / (d[c] - d[e]);
      for (int k = 0; k < 2; ++k) {
        const int a = s.plane_axes[k];
        pts[n][k] = m.vertices[t[c]][a] + w * (m.vertices[t[e]][a] - m.vertices[t[c]][a]);
      }
      ++n;
    }
    if (n == 2) s.segments.push_back({pts[0][0], pts[0][1], pts[1][0], pts[1][1]});
  }
  return s;
}

// The part scaled into the unit cube, with area-weighted vertex normals, coloured by height
// from -1 (bottom) to +1 (top) on the diverging scale.
DrawSurface unit_cube_view(const TriMesh& m) {
  const MeshStats box = bounding_box(m);
  const double extent =
      std::max({box.max[0] - box.min[0], box.max[1] - box.min[1], box.max[2] - box.min[2], 1e-30});
  DrawSurface s;
  s.origin = 0.0f;
  s.positions.resize(m.vertices.size());
  std::vector<Vec3> normal(m.vertices.size(), Vec3{0, 0, 0});
  for (std::size_t v = 0; v < m.vertices.size(); ++v)
    for (int c = 0; c < 3; ++c)
      s.positions[v][c] = float(0.5 + (m.vertices[v][c] - 0.5 * (box.min[c] + box.max[c])) /
                                          extent * 0.999);
  for (const auto& t : m.triangles) {
    const Vec3 n = cross(sub(m.vertices[t[1]], m.vertices[t[0]]),
                         sub(m.vertices[t[2]], m.vertices[t[0]]));
    for (std::uint32_t v : t)
      for (int c = 0; c < 3; ++c) normal[v][c] += n[c];
  }
  s.normals.resize(m.vertices.size());
  s.curvature.resize(m.vertices.size());
  const double height = std::max(box.max[2] - box.min[2], 1e-30);
  for (std::size_t v = 0; v < m.vertices.size(); ++v) {
    const double len = std::sqrt(dot(normal[v], normal[v]));
    for (int c = 0; c < 3; ++c) s.normals[v][c] = len > 0 ? float(normal[v][c] / len) : 0.0f;
    s.curvature[v] = float(2.0 * (m.vertices[v][2] - box.min[2]) / height - 1.0);
  }
  s.triangles = m.triangles;
  return s;
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("cannot read '{}'", path.string()));
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A row of the part's tables: a JSON pointer into FILE.json, its label and format.
struct PartRow {
  const char* pointer;
  const char* label;
  const char* format;
};

constexpr PartRow kPartRows[] = {
    {"/porosity", "porosity", "{:.4f}"},
    {"/porosity_error", "porosity − target", "{:+.1e}"},
    {"/design/cell_size", "cell size", "{:.4g}"},
    {"/sheet/thickness", "wall (sheet thickness, solved)", "{:.4g}"},
    {"/morphometry/wall_thickness/mean", "wall mean", "{:.4g}"},
    {"/morphometry/wall_thickness/min", "wall min", "{:.4g}"},
    {"/morphometry/pore_size/mean", "pore mean", "{:.4g}"},
    {"/morphometry/pore_size/min", "pore min", "{:.4g}"},
    {"/morphometry/specific_surface", "specific surface (1/unit)", "{:.4g}"},
    {"/volume", "solid volume (unit³)", "{:.6g}"},
    {"/area", "surface area (unit²)", "{:.6g}"},
    {"/triangles", "triangles", "{:.0f}"},
    {"/triangles_unsimplified", "triangles before decimation", "{:.0f}"},
    {"/decimation/error", "decimation error (symmetric, sampled)", "{:.3g}"},
    {"/decimation/hausdorff_bound", "decimation Hausdorff bound", "{:.3g}"},
    {"/file_bytes", "file bytes", "{:.0f}"},
    {"/topology/fragments", "fragments cut off", "{:.0f}"},
    {"/topology/closed_pores", "closed pores", "{:.0f}"},
};

constexpr PartRow kCompareRows[] = {
    {"/porosity", "porosity", "{:.5f}"},
    {"/mean_curvature_std", "mean curvature std (1/unit)", "{:.4g}"},
    {"/specific_surface", "specific surface (1/unit)", "{:.4g}"},
    {"/wall_thickness/mean", "wall mean", "{:.4g}"},
    {"/wall_thickness/std", "wall std", "{:.3g}"},
    {"/wall_thickness/min", "wall min", "{:.4g}"},
    {"/pore_size/mean", "pore mean", "{:.4g}"},
    {"/pore_size/std", "pore std", "{:.3g}"},
    {"/pore_size/min", "pore min", "{:.4g}"},
    {"/thickness", "sheet thickness", "{:.5g}"},
};

// One cell with its JSON pointer and all 17 digits, as properties_table_html.
std::string value_cell(const nlohmann::json& report, const std::string& path, const char* format) {
  const nlohmann::json::json_pointer at(path);
  if (!report.contains(at) || !report[at].is_number())
    return fmt::format("<td data-path=\"{}\">–</td>", html_escape(path));
  const double v = report[at].get<double>();
  return fmt::format("<td data-path=\"{}\" data-value=\"{:.17g}\">{}</td>", html_escape(path), v,
                     html_escape(format_number(format, v)));
}

std::string part_table(const nlohmann::json& report) {
  std::string out = "<table class=\"numbers\" id=\"part\">\n";
  const std::string units = report.value("units", std::string("mm"));
  for (const PartRow& row : kPartRows) {
    const nlohmann::json::json_pointer at(row.pointer);
    if (!report.contains(at) || !report[at].is_number()) continue;
    std::string label = row.label;
    if (const auto u = label.find("unit"); u != std::string::npos) label.replace(u, 4, units);
    else if (std::string(row.format) != "{:.0f}" && label.find("porosity") == std::string::npos)
      label += " (" + units + ")";
    out += fmt::format("<tr><th>{}</th>{}</tr>\n", html_escape(label),
                       value_cell(report, row.pointer, row.format));
  }
  return out + "</table>\n";
}

std::string compare_table(const nlohmann::json& report) {
  const nlohmann::json& c = report["compare_nodal"];
  if (!c.contains("cmc") || !c.contains("nodal") || c["nodal"].contains("error")) return "";
  const std::string units = report.value("units", std::string("mm"));
  std::string out = "<table class=\"numbers\" id=\"compare-nodal\">\n<tr><th></th><th>CMC</th>"
                    "<th>nodal</th></tr>\n";
  for (const PartRow& row : kCompareRows) {
    const std::string a = std::string("/compare_nodal/cmc") + row.pointer,
                      b = std::string("/compare_nodal/nodal") + row.pointer;
    if (!report.contains(nlohmann::json::json_pointer(a))) continue;
    std::string label = row.label;
    if (const auto u = label.find("unit"); u != std::string::npos) label.replace(u, 4, units);
    else if (label != "porosity") label += " (" + units + ")";
    out += fmt::format("<tr><th>{}</th>{}{}</tr>\n", html_escape(label),
                       value_cell(report, a, row.format), value_cell(report, b, row.format));
  }
  return out + "</table>\n";
}

std::string slice_svg(const PartSlice& s, const std::string& units) {
  const double w = std::max(s.hi[0] - s.lo[0], 1e-30), h = std::max(s.hi[1] - s.lo[1], 1e-30);
  const double px = 360.0 / std::max(w, h);
  std::string d;
  d.reserve(s.segments.size() * 28);
  for (const auto& g : s.segments)
    d += fmt::format("M{:.1f} {:.1f}L{:.1f} {:.1f}", (g[0] - s.lo[0]) * px,
                     (s.hi[1] - g[1]) * px, (g[2] - s.lo[0]) * px, (s.hi[1] - g[3]) * px);
  const char* names = "xyz";
  return fmt::format(
      "<figure class=\"slice\"><svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0f}\" "
      "height=\"{:.0f}\" data-segments=\"{}\"><rect width=\"100%\" height=\"100%\" fill=\"none\" "
      "stroke=\"#bbb\"/><path d=\"{}\" stroke=\"#222\" stroke-width=\"0.7\" fill=\"none\"/></svg>"
      "<figcaption>cut at {} = {:.4g} {} ({} horizontal, {} up)</figcaption></figure>\n",
      w * px, h * px, s.segments.size(), d, names[s.axis], s.at, units, names[s.plane_axes[0]],
      names[s.plane_axes[1]]);
}

// Bars of one local-thickness histogram (morphometry's fractions of the phase per bin).
std::string histogram_svg(const nlohmann::json& stats, const std::string& title,
                          const std::string& color, const std::string& units) {
  if (!stats.contains("histogram") || !stats.contains("histogram_edges")) return "";
  const std::vector<double> counts = stats["histogram"].get<std::vector<double>>();
  const std::vector<double> edges = stats["histogram_edges"].get<std::vector<double>>();
  if (counts.empty() || edges.size() != counts.size() + 1) return "";
  const double W = 360, H = 200, L = 40, R = 10, T = 24, B = 30;
  const double x0 = edges.front(), x1 = std::max(edges.back(), x0 + 1e-30);
  const double top = std::max(*std::max_element(counts.begin(), counts.end()), 1e-30);
  std::string bars;
  for (std::size_t i = 0; i < counts.size(); ++i) {
    const double a = L + (edges[i] - x0) / (x1 - x0) * (W - L - R);
    const double b = L + (edges[i + 1] - x0) / (x1 - x0) * (W - L - R);
    const double y = T + (1 - counts[i] / top) * (H - T - B);
    bars += fmt::format("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" "
                        "fill=\"{}\"/>", a, y, std::max(b - a - 0.5, 0.5), H - B - y, color);
  }
  return fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"chart\" width=\"{:.0f}\" "
      "height=\"{:.0f}\" data-title=\"{}\"><text x=\"{:.0f}\" y=\"14\">{}</text><rect x=\"{:.0f}\" "
      "y=\"{:.0f}\" width=\"{:.0f}\" height=\"{:.0f}\" fill=\"none\" stroke=\"#bbb\"/>{}"
      "<text x=\"{:.0f}\" y=\"{:.0f}\">{}</text><text x=\"{:.0f}\" y=\"{:.0f}\" "
      "text-anchor=\"end\">{}</text><text x=\"{:.0f}\" y=\"{:.0f}\" text-anchor=\"middle\">"
      "local thickness ({})</text></svg>\n",
      W, H, html_escape(title), L, html_escape(title), L, T, W - L - R, H - T - B, bars, L,
      H - B + 14, format_number("{:.3g}", x0), W - R, H - B + 14, format_number("{:.3g}", x1),
      (L + W) / 2, H - 2, html_escape(units));
}

std::string distributions_html(const nlohmann::json& report) {
  if (!report.contains("morphometry")) return "";
  const nlohmann::json& m = report["morphometry"];
  const std::string units = report.value("units", std::string("mm"));
  std::string out;
  auto cell = [&](const nlohmann::json& c, const std::string& name) {
    if (c.contains("wall_thickness"))
      out += histogram_svg(c["wall_thickness"], "wall" + name, "#2b5cd6", units);
    if (c.contains("pore_size"))
      out += histogram_svg(c["pore_size"], "pore" + name, "#e07b1a", units);
  };
  cell(m, "");
  if (m.contains("members"))
    for (const auto& c : m["members"])
      cell(c, fmt::format(" (member at porosity {:.2f})", c.value("porosity", 0.0)));
  if (out.empty()) return "";
  return "<h2>Wall and pore distributions (local thickness on the unit cell)</h2>\n"
         "<div class=\"charts\" id=\"distributions\">\n" + out + "</div>\n";
}

}  // namespace

PartPageMeasures measure_part_page(const TriMesh& part, std::size_t max_triangles) {
  PartPageMeasures m;
  auto t0 = WallClock::now();
  m.part_triangles = part.triangles.size();
  if (part.triangles.size() > max_triangles) {
    CollapseParams p;
    p.target_triangles = max_triangles;
    m.view = unit_cube_view(collapse_edges(part, {}, p));
  } else {
    m.view = unit_cube_view(part);
  }
  m.view_triangles = m.view.triangles.size();
  m.view_seconds = seconds_since(t0);
  t0 = WallClock::now();
  const MeshStats box = bounding_box(part);
  m.slices = {slice_mesh(part, box, 2, 0.4), slice_mesh(part, box, 0, 0.4)};
  m.slice_seconds = seconds_since(t0);
  return m;
}

nlohmann::json part_page_seconds(const PartPageMeasures& m) {
  return {{"page_view", m.view_seconds}, {"page_slices", m.slice_seconds}};
}

double write_part_page(const fs::path& html, const fs::path& png, const nlohmann::json& report,
                       const PartPageMeasures& m) {
  const auto t0 = WallClock::now();
  const std::string units = report.value("units", std::string("mm"));
  const nlohmann::json design = report.value("design", nlohmann::json::object());
  const std::string surface =
      report.contains("/member/parameters/surface"_json_pointer)
          ? report["/member/parameters/surface"_json_pointer].get<std::string>()
          : std::string("");
  const std::string solid = design.value("solid", std::string("?"));
  ReportPage page;
  page.title = fmt::format("cmcsurf part: {}{}{}, porosity {:.4f}", surface,
                           surface.empty() ? "" : " ", solid, report.value("porosity", 0.0));
  page.subtitle = fmt::format(
      "{}: {} of {} triangles drawn, coloured by height. Cell size {:g} {}. Drag to rotate, "
      "scroll to zoom.",
      html.filename().string(), m.view_triangles, m.part_triangles,
      design.value("cell_size", 0.0), units);
  page.body = "<h2>The part</h2>\n" + part_table(report);
  if (report.contains("compare_nodal")) {
    const std::string t = compare_table(report);
    if (!t.empty()) page.body += "<h2>CMC against nodal (--compare-nodal)</h2>\n" + t;
  }
  if (report.contains("properties") && report["properties"].is_object())
    page.body += "<h2>Stiffness and conductivity of the unit cell (docs/properties.md)</h2>\n" +
                 properties_table_html(report["properties"]);
  page.body += "<h2>Slices</h2>\n<div class=\"charts\" id=\"slices\">\n";
  for (const PartSlice& s : m.slices) page.body += slice_svg(s, units);
  page.body += "</div>\n" + distributions_html(report);
  ColorScale scale;
  scale.centre = 0.0;
  scale.half_range = 1.0;
  page.data = {{"kind", "part"}, {"scale", color_scale_json(scale)}, {"part", mesh_json(m.view)}};
  write_file_atomic(html, report_page_html(page));
  Image preview = render_panel(m.view, 1, scale, 640);
  draw_text(preview, 12, 28, 20.0f, page.title, {0, 0, 0});
  write_png(png, preview);
  return seconds_since(t0);
}

fs::path part_page_path(const fs::path& part) { return fs::path(part.string() + ".html"); }
fs::path part_preview_path(const fs::path& part) { return fs::path(part.string() + ".png"); }

double write_part_page_from_report(const fs::path& report_json) {
  const auto t0 = WallClock::now();
  nlohmann::json report;
  try {
    report = nlohmann::json::parse(read_text(report_json));
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(
        fmt::format("'{}' is not valid JSON: {}", report_json.string(), e.what()));
  }
  std::string name = report_json.string();
  if (name.size() <= 5 || name.substr(name.size() - 5) != ".json")
    throw std::runtime_error(fmt::format("'{}': a part's report is FILE.json", name));
  const fs::path part(name.substr(0, name.size() - 5));
  if (!fs::is_regular_file(part))
    throw std::runtime_error(fmt::format("'{}': its part '{}' is missing", name, part.string()));
  std::string ext = part.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  TriMesh mesh;
  if (ext == ".3mf") mesh = read_3mf(part).mesh;
  else if (ext == ".stl") mesh = read_stl(part);
  else
    throw std::runtime_error(fmt::format(
        "'{}': a page is made from a 3MF or STL part (write the part as one of them)",
        part.string()));
  const PartPageMeasures m = measure_part_page(mesh);
  write_part_page(part_page_path(part), part_preview_path(part), report, m);
  return seconds_since(t0);
}

}  // namespace cmcsurf
