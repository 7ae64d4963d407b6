#include "report/part_page.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>
#include <string>

#include "common/wall_clock.h"
#include "common/atomic_file.h"
#include "common/input_file.h"
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
      cell(c, c.contains("cell_size")
                  ? fmt::format(" (cell size {:g} {})", c.value("cell_size", 0.0), units)
                  : fmt::format(" (cell at porosity {:.2f})", c.value("porosity", 0.0)));
  if (out.empty()) return "";
  return "<h2>Wall and pore distributions (local thickness on the unit cell)</h2>\n"
         "<div class=\"charts\" id=\"distributions\">\n" + out + "</div>\n";
}

// A graded part's profile in FILE.json: the porosity ramp's (`graded`, along an axis or by
// depth below a shape's surface) or a graded cell size's (one porosity, `graded_cell_size`).
struct GradedProfile {
  std::string pointer;  // of the bands' array
  bool by_depth = false;
  std::string where;    // "along z", "by depth below the surface"
};

std::vector<GradedProfile> graded_profiles(const nlohmann::json& report) {
  std::vector<GradedProfile> out;
  for (const char* key : {"graded", "graded_cell_size"}) {
    if (!report.contains(key) || !report[key].is_object()) continue;
    const nlohmann::json& g = report[key];
    if (!g.contains("profile") || !g["profile"].is_array() || g["profile"].empty()) continue;
    const bool depth = g.value("by", std::string("axis")) == "surface";
    const std::string axis = g.contains("axis") && g["axis"].is_string()
                                 ? g["axis"].get<std::string>() : std::string("?");
    out.push_back({std::string("/") + key + "/profile", depth,
                   depth ? "by depth below the surface" : "along " + axis});
  }
  return out;
}

double number_or_nan(const nlohmann::json& band, const char* key) {
  return band.contains(key) && band[key].is_number() ? band[key].get<double>() : NAN;
}

// Where each band sits on the chart's x axis (output units): an axis band's middle; a depth
// band's middle, the core (depth_to null) drawn one band wide past the last.
std::vector<std::array<double, 3>> band_places(const nlohmann::json& bands, bool by_depth) {
  std::vector<std::array<double, 3>> at;  // from, middle, to
  double width = 0.0;
  for (const auto& b : bands) {
    double from = number_or_nan(b, by_depth ? "depth_from" : "from");
    double to = number_or_nan(b, by_depth ? "depth_to" : "to");
    if (std::isnan(to)) to = from + width;
    width = to - from;
    at.push_back({from, 0.5 * (from + to), to});
  }
  return at;
}

// Target (line) and measured (dots) porosity per band: FILE.json's numbers, drawn.
std::string profile_svg(const nlohmann::json& bands, const GradedProfile& g,
                        const std::string& units) {
  const auto at = band_places(bands, g.by_depth);
  double lo = 1.0, hi = 0.0;
  for (const auto& b : bands)
    for (const char* key : {"porosity_target", "porosity_nodes"})
      if (const double v = number_or_nan(b, key); !std::isnan(v)) lo = std::min(lo, v),
                                                                   hi = std::max(hi, v);
  if (!(hi >= lo)) return "";
  lo = std::max(0.0, lo - 0.02), hi = std::min(1.0, hi + 0.02);
  const double W = 480, H = 240, L = 48, R = 12, T = 26, B = 34;
  const double x0 = at.front()[0], x1 = std::max(at.back()[2], x0 + 1e-30);
  auto X = [&](double x) { return L + (x - x0) / (x1 - x0) * (W - L - R); };
  auto Y = [&](double y) { return T + (hi - y) / std::max(hi - lo, 1e-30) * (H - T - B); };
  std::string line, dots;
  int drawn = 0;
  for (std::size_t i = 0; i < at.size(); ++i) {
    const double target = number_or_nan(bands[i], "porosity_target"),
                 nodes = number_or_nan(bands[i], "porosity_nodes");
    if (!std::isnan(target))
      line += fmt::format("{}{:.1f} {:.1f}", line.empty() ? "M" : "L", X(at[i][1]), Y(target));
    if (!std::isnan(nodes)) {
      dots += fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"4\" fill=\"#e07b1a\"/>",
                          X(at[i][1]), Y(nodes));
      ++drawn;
    }
  }
  const std::string x_label = g.by_depth
                                  ? fmt::format("depth below the surface ({}); last: the core",
                                                units)
                                  : fmt::format("position {} ({})", g.where, units);
  return fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"chart\" width=\"{:.0f}\" "
      "height=\"{:.0f}\" data-title=\"porosity profile\" data-bands=\"{}\" data-drawn=\"{}\">"
      "<text x=\"{:.0f}\" y=\"14\">porosity {}: target (line), measured (dots)</text>"
      "<rect x=\"{:.0f}\" y=\"{:.0f}\" width=\"{:.0f}\" height=\"{:.0f}\" fill=\"none\" "
      "stroke=\"#bbb\"/><path d=\"{}\" stroke=\"#2b5cd6\" stroke-width=\"2\" fill=\"none\"/>{}"
      "<text x=\"{:.0f}\" y=\"{:.0f}\" text-anchor=\"end\">{}</text>"
      "<text x=\"{:.0f}\" y=\"{:.0f}\" text-anchor=\"end\">{}</text>"
      "<text x=\"{:.0f}\" y=\"{:.0f}\">{}</text><text x=\"{:.0f}\" y=\"{:.0f}\" "
      "text-anchor=\"end\">{}</text><text x=\"{:.0f}\" y=\"{:.0f}\" text-anchor=\"middle\">"
      "{}</text></svg>\n",
      W, H, bands.size(), drawn, L, html_escape(g.where), L, T, W - L - R, H - T - B, line,
      dots, L - 4, T + 10, format_number("{:.3f}", hi), L - 4, H - B, format_number("{:.3f}", lo),
      L, H - B + 14, format_number("{:.3g}", x0), W - R, H - B + 14,
      format_number("{:.3g}", x1), (L + W) / 2, H - 2, html_escape(x_label));
}

}  // namespace

// The graded profile: the chart, its numbers (each cell FILE.json's, by its pointer), and the
// wall and pore of each member's cell (a ramp's members, a graded sheet's two ends).
std::string graded_profile_html(const nlohmann::json& report) {
  const std::string units = report.value("units", std::string("mm"));
  std::string out;
  for (const GradedProfile& g : graded_profiles(report)) {
    const nlohmann::json& bands = report[nlohmann::json::json_pointer(g.pointer)];
    out += fmt::format("<h2>Porosity {}: target and measured</h2>\n", html_escape(g.where));
    out += "<p>Measured: the fraction of the part's lattice nodes outside the solid in each "
           "band (FILE.json's <code>" + html_escape(g.pointer) + "</code>).</p>\n";
    out += "<div class=\"charts\" id=\"profile\">\n" + profile_svg(bands, g, units) + "</div>\n";
    out += fmt::format("<table class=\"numbers\" id=\"profile-bands\">\n<tr><th>{} ({})</th>"
                       "<th>porosity target</th><th>porosity measured</th></tr>\n",
                       g.by_depth ? "depth" : g.where, html_escape(units));
    const auto at = band_places(bands, g.by_depth);
    for (std::size_t i = 0; i < bands.size(); ++i) {
      const bool core =
          g.by_depth && bands[i].contains("depth_to") && bands[i]["depth_to"].is_null();
      const std::string place = core ? fmt::format("{} – core", format_number("{:.3g}", at[i][0]))
                                     : fmt::format("{} – {}", format_number("{:.3g}", at[i][0]),
                                                   format_number("{:.3g}", at[i][2]));
      const std::string row = fmt::format("{}/{}/", g.pointer, i);
      out += fmt::format("<tr><th>{}</th>{}{}</tr>\n", html_escape(place),
                         value_cell(report, row + "porosity_target", "{:.4f}"),
                         value_cell(report, row + "porosity_nodes", "{:.4f}"));
    }
    out += "</table>\n";
  }
  if (out.empty() || !report.contains("/morphometry/members"_json_pointer)) return out;
  const nlohmann::json& members = report["/morphometry/members"_json_pointer];
  if (!members.is_array() || members.empty()) return out;
  const bool by_cell = members[0].contains("cell_size");
  out += fmt::format("<h2>Wall and pore of the cells the part blends (local thickness on each "
                     "unit cell)</h2>\n<table class=\"numbers\" id=\"members\">\n<tr><th>{}"
                     "</th><th>wall mean</th><th>wall min</th><th>pore mean</th><th>pore min"
                     "</th></tr>\n",
                     by_cell ? "cell size (" + html_escape(units) + ")" : "porosity");
  for (std::size_t i = 0; i < members.size(); ++i) {
    const std::string at = fmt::format("/morphometry/members/{}/", i);
    out += fmt::format("<tr>{}{}{}{}{}</tr>\n",
                       value_cell(report, at + (by_cell ? "cell_size" : "porosity"), "{:.4g}"),
                       value_cell(report, at + "wall_thickness/mean", "{:.4g}"),
                       value_cell(report, at + "wall_thickness/min", "{:.4g}"),
                       value_cell(report, at + "pore_size/mean", "{:.4g}"),
                       value_cell(report, at + "pore_size/min", "{:.4g}"));
  }
  return out + "</table>\n<p>Wall and pore in " + html_escape(units) + ".</p>\n";
}

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
  // A graded network's `member` holds its members: the surface is the first one's.
  std::string surface;
  for (const char* at : {"/member/parameters/surface", "/member/members/0/parameters/surface"})
    if (const nlohmann::json::json_pointer p(at); surface.empty() && report.contains(p) &&
                                                  report[p].is_string())
      surface = report[p].get<std::string>();
  const std::string solid = design.value("solid", std::string("?"));
  // A porosity ramp: its ends, and the mean the part meets.
  const nlohmann::json graded = report.value("graded", nlohmann::json::object());
  const std::string ramp =
      graded.contains("porosity_from") && graded.contains("porosity_to")
          ? fmt::format("{:g} to {:g}, mean ", graded["porosity_from"].get<double>(),
                        graded["porosity_to"].get<double>())
          : std::string();
  ReportPage page;
  page.title = fmt::format("cmcsurf part: {}{}{}, porosity {}{:.4f}", surface,
                           surface.empty() ? "" : " ", solid, ramp, report.value("porosity", 0.0));
  page.subtitle = fmt::format(
      "{}: {} of {} triangles drawn, coloured by height. Cell size {:g} {}. Drag to rotate, "
      "scroll to zoom.",
      html.filename().string(), m.view_triangles, m.part_triangles,
      design.value("cell_size", 0.0), units);
  page.body = "<h2>The part</h2>\n" + part_table(report) + graded_profile_html(report);
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
    report = nlohmann::json::parse(read_input_file(report_json, "input file"));
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
