#include "report/run_page.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "common/wall_clock.h"
#include "common/atomic_file.h"
#include "common/input_file.h"
#include "io/png.h"
#include "io/pvti.h"
#include "report/report_html.h"
#include "io/vti.h"
#include "pipeline/preview.h"
#include "pipeline/properties_pictures.h"
#include "pipeline/sweep.h"
#include "schema/report_schema.h"

namespace cmcsurf {

namespace fs = std::filesystem;

namespace {

nlohmann::json read_json_file(const fs::path& path) {
  const std::string text = read_input_file(path, "input file");
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(fmt::format("'{}' is not valid JSON: {}", path.string(), e.what()));
  }
}

// The text of a CSV file of numbers (and bare words) with a header, as columns:
// {name: [values]}. Numbers stay numbers, anything else a string. `path` names it in messages.
nlohmann::json csv_columns(const std::string& text, const fs::path& path) {
  std::istringstream in(text);
  std::string line;
  std::vector<std::string> names;
  nlohmann::json columns = nlohmann::json::object();
  auto split = [](const std::string& l) {
    std::vector<std::string> cells;
    std::string cell;
    for (char c : l) {
      if (c == ',') {
        cells.push_back(cell);
        cell.clear();
      } else if (c != '\r' && c != '"') {
        cell += c;
      }
    }
    cells.push_back(cell);
    return cells;
  };
  if (!std::getline(in, line))
    throw std::runtime_error(fmt::format("'{}' is empty: no header", path.string()));
  names = split(line);
  for (const std::string& n : names) columns[n] = nlohmann::json::array();
  int row = 1;
  while (std::getline(in, line)) {
    ++row;
    if (line.empty()) continue;
    const std::vector<std::string> cells = split(line);
    if (cells.size() != names.size())
      throw std::runtime_error(fmt::format("'{}' line {}: {} cells, the header has {}",
                                           path.string(), row, cells.size(), names.size()));
    for (std::size_t c = 0; c < cells.size(); ++c) {
      char* end = nullptr;
      const double v = std::strtod(cells[c].c_str(), &end);
      if (!cells[c].empty() && end == cells[c].c_str() + cells[c].size())
        columns[names[c]].push_back(std::isfinite(v) ? nlohmann::json(v) : nlohmann::json());
      else
        columns[names[c]].push_back(cells[c]);
    }
  }
  return columns;
}

nlohmann::json read_csv_columns(const fs::path& path) {
  return csv_columns(read_input_file(path, "input file"), path);
}

// psi = atanh(2 phi - 1) of a folder's field.vti (or field.pvti), for preview_surfaces.
Field read_psi(const fs::path& dir) {
  VtiReadOptions options;
  options.ghost = 2;
  options.only = "phi";
  VtiData data = read_field_file(run_field_file(dir), options);
  return profile_inverse(data.arrays.at("phi"));
}

double number_or(const nlohmann::json& j, const char* key, double fallback) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : fallback;
}

std::string png_data_url(const fs::path& path) {
  return "data:image/png;base64," + base64(read_input_file(path, "input file"));
}

// A sweep folder's sweep.json: its surfaces and volume fractions, the members' names' axes.
struct SweepAxes {
  std::vector<std::string> surfaces;
  std::vector<double> fractions;
};

SweepAxes read_sweep_axes(const fs::path& summary_path) {
  const nlohmann::json summary = read_json_file(summary_path);
  SweepAxes axes;
  try {
    axes.surfaces = summary.at("surfaces").get<std::vector<std::string>>();
    axes.fractions = summary.at("volume_fractions").get<std::vector<double>>();
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(fmt::format("'{}' lacks surfaces or volume_fractions: {}",
                                         summary_path.string(), e.what()));
  }
  return axes;
}

}  // namespace

namespace {

// The page of a run folder from its report and columns; the meshes from `surfaces` or, when
// null, from the folder's field.
void write_run_page_of(const fs::path& dir, const PreviewSurfaces* surfaces,
                       const nlohmann::json& report, const nlohmann::json& history,
                       const nlohmann::json& histogram) {
  const std::string surface = report.value("surface", std::string("?"));
  const double h = number_or(report, "mean_curvature", 0.0);
  const bool nodal = report.contains("nodal_level") && report["nodal_level"].is_number();
  const PreviewSurfaces s =
      surfaces ? *surfaces
               : preview_surfaces(read_psi(dir), surface, number_or(report, "nodal_level", 0.0), h,
                                  kPageCells, nodal);
  const double alpha = number_or(report, "volume_fraction_target",
                                 number_or(report, "volume_fraction", 0.0));

  ReportPage page;
  page.title = fmt::format("cmcsurf: {}  α = {:.4g}  H = {:+.5g}", surface, alpha, h);
  page.subtitle = fmt::format(
      "{}³ cells, ε = {:.3g}; the φ = 1/2 surface coloured by its local mean curvature on a "
      "diverging scale centred on H. Drag to rotate, scroll to zoom.",
      report.value("grid", 0), number_or(report, "epsilon", 0.0));
  page.body = "<h2>Key numbers</h2>\n" + numbers_table_html(report, run_number_rows(), "numbers");
  if (report.contains("properties") && report["properties"].is_object()) {
    // The --properties stage: the network's stiffness and conductivities beside its nodal
    // twin's, and the directional Young's modulus when the run drew it.
    page.body += "<h2>Stiffness and conductivity of the network (docs/properties.md)</h2>\n" +
                 properties_table_html(report["properties"]);
    if (fs::exists(dir / kYoungsPictureName))
      page.body += "<img class=\"plot\" alt=\"youngs_modulus\" src=\"" +
                   png_data_url(dir / kYoungsPictureName) + "\">\n";
  }
  page.body +=
      "<h2>Convergence</h2>\n<div class=\"charts\" id=\"history\"></div>\n"
      "<h2>Local mean curvature</h2>\n<div class=\"charts\" id=\"histogram\"></div>\n";
  page.data = {{"kind", "run"},
               {"scale", color_scale_json(s.scale)},
               {"mean_curvature", h},
               {"relaxed", mesh_json(s.relaxed)},
               {"nodal", s.has_nodal ? mesh_json(s.nodal) : nlohmann::json()},
               {"history", history},
               {"histogram", histogram}};
  write_file_atomic(dir / "report.html", report_page_html(page));
}

}  // namespace

double write_run_page(const fs::path& dir, const PreviewSurfaces* surfaces) {
  const auto t0 = WallClock::now();
  const fs::path report_path = dir / "report.json";
  if (!fs::exists(report_path))
    throw std::runtime_error(fmt::format(
        "'{}' has no report.json: not a complete run folder (a run writes it last)", dir.string()));
  const nlohmann::json report = read_json_file(report_path);
  const nlohmann::json history = read_csv_columns(dir / "history.csv");
  const nlohmann::json histogram = read_csv_columns(dir / "curvature_histogram.csv");
  write_run_page_of(dir, surfaces, report, history, histogram);
  return seconds_since(t0);
}

double write_run_page(const fs::path& dir, const PreviewSurfaces& surfaces,
                      const RunPageData& data) {
  const auto t0 = WallClock::now();
  const nlohmann::json history = csv_columns(data.history_csv, dir / "history.csv");
  const nlohmann::json histogram =
      csv_columns(data.curvature_histogram_csv, dir / "curvature_histogram.csv");
  write_run_page_of(dir, &surfaces, data.report, history, histogram);
  return seconds_since(t0);
}

double write_sweep_page(const fs::path& dir) {
  const auto t0 = WallClock::now();
  const fs::path summary_path = dir / "sweep.json";
  if (!fs::exists(summary_path))
    throw std::runtime_error(fmt::format(
        "'{}' has no sweep.json: not a complete sweep folder (a sweep writes it last)",
        dir.string()));
  const auto [surfaces, fractions] = read_sweep_axes(summary_path);
  nlohmann::json members = nlohmann::json::array();
  std::vector<nlohmann::json> reports;
  double reach = 0.0;
  std::string table = "<table class=\"members\" id=\"members\">\n<tr><th>member</th>";
  for (const ReportKey& k : report_key_table())
    if (!k.sweep_page.header.empty()) table += fmt::format("<th>{}</th>", k.sweep_page.header);
  table += "</tr>\n";
  for (std::size_t si = 0; si < surfaces.size(); ++si)
    for (double alpha : fractions) {
      const std::string name =
          checked_member_name(surfaces[si], int(si), alpha, summary_path.string());
      const fs::path member = dir / name;
      const nlohmann::json report = read_json_file(member / "report.json");
      const double h = number_or(report, "mean_curvature", 0.0);
      const PreviewSurfaces s =
          preview_surfaces(read_psi(member), surfaces[si], 0.0, h, kSweepMemberCells, false);
      reach = std::max(reach, std::abs(h) + curvature_spread(s.relaxed, h, 0.95));
      members.push_back({{"name", name},
                         {"surface", surfaces[si]},
                         {"alpha", alpha},
                         {"mean_curvature", h},
                         {"mesh", mesh_json(s.relaxed)}});
      std::string cells;
      for (const ReportKey& k : report_key_table()) {
        if (k.sweep_page.header.empty()) continue;
        const auto v = report.find(k.key);
        if (v == report.end() || !v->is_number()) {
          cells += fmt::format("<td data-key=\"{}\">–</td>", k.key);
          continue;
        }
        cells += fmt::format("<td data-key=\"{}\" data-value=\"{:.17g}\">{}</td>", k.key,
                             v->get<double>(),
                             format_report_number(k.sweep_page.format, v->get<double>()));
      }
      table += fmt::format("<tr class=\"member\" data-member=\"{}\"><td>{}</td>{}</tr>\n",
                           html_escape(name), html_escape(name), cells);
      reports.push_back(report);
    }
  table += "</table>\n";
  ColorScale scale;
  scale.centre = 0.0;
  scale.half_range = std::max(reach, 1e-3);

  ReportPage page;
  page.title = fmt::format("cmcsurf sweep: {} members", members.size());
  std::string names;
  for (const std::string& s : surfaces) names += (names.empty() ? "" : ", ") + s;
  page.subtitle = fmt::format(
      "{} at α = {:.4g} … {:.4g}; the unit cell of the selected member (click a row) coloured by "
      "local H on one scale centred on 0 for every member.",
      names, fractions.front(), fractions.back());
  page.body = "<h2>Members</h2>\n" + table;
  if (fs::exists(dir / "families.png"))
    page.body += "<h2>Families (Fig. 11)</h2>\n<img class=\"plot\" alt=\"families\" src=\"" +
                 png_data_url(dir / "families.png") + "\">\n";
  if (fs::exists(dir / kPropertiesChartName))
    page.body += "<h2>Stiffness and conductivity against density (docs/properties.md)</h2>\n"
                 "<img class=\"plot\" alt=\"properties_chart\" src=\"" +
                 png_data_url(dir / kPropertiesChartName) + "\">\n";
  if (fs::exists(dir / "gallery.png"))
    page.body += "<h2>Gallery</h2>\n<img class=\"plot\" alt=\"gallery\" src=\"" +
                 png_data_url(dir / "gallery.png") + "\">\n";
  page.data = {{"kind", "sweep"}, {"scale", color_scale_json(scale)}, {"members", members}};
  write_file_atomic(dir / "report.html", report_page_html(page));
  return seconds_since(t0);
}

double write_gallery(const fs::path& dir, const std::vector<GalleryMember>& members) {
  const auto t0 = WallClock::now();
  std::vector<GalleryRow> rows;
  double reach = 0.0;
  std::string families;
  for (const GalleryMember& m : members) {
    if (rows.empty() || rows.back().family != m.surface) {
      rows.push_back({m.surface, {}});
      families += (families.empty() ? "" : ", ") + m.surface;
    }
    rows.back().tiles.push_back(
        {&m.relaxed, fmt::format("α {:.3g}   H {:+.3f}", m.alpha, m.mean_curvature)});
    reach = std::max(reach, std::abs(m.mean_curvature) +
                                curvature_spread(m.relaxed, m.mean_curvature, 0.95));
  }
  for (GalleryRow& r : rows)
    if (r.family.size() > 12) r.family = r.family.substr(0, 10) + "…";
  ColorScale scale;
  scale.half_range = std::max(reach, 1e-3);
  Image plot;
  if (fs::exists(dir / "families.png")) plot = read_png(dir / "families.png");
  const Image img = render_gallery(
      fmt::format("{}: unit cells coloured by local mean curvature H (one scale, centred on 0)",
                  families),
      rows, scale, plot);
  write_png(dir / "gallery.png", img);
  return seconds_since(t0);
}

GalleryMember gallery_member_from_folder(const fs::path& member_dir, const std::string& surface,
                                         const std::string& name, double alpha) {
  const nlohmann::json report = read_json_file(member_dir / "report.json");
  const double h = number_or(report, "mean_curvature", 0.0);
  PreviewSurfaces s = preview_surfaces(read_psi(member_dir), surface, 0.0, h, kPreviewCells, false);
  return {surface, name, alpha, h, std::move(s.relaxed)};
}

double write_gallery_from_folder(const fs::path& dir) {
  const auto t0 = WallClock::now();
  const fs::path summary_path = dir / "sweep.json";
  const auto [surfaces, fractions] = read_sweep_axes(summary_path);
  std::vector<GalleryMember> members;
  for (std::size_t si = 0; si < surfaces.size(); ++si)
    for (double alpha : fractions) {
      const std::string name =
          checked_member_name(surfaces[si], int(si), alpha, summary_path.string());
      members.push_back(gallery_member_from_folder(dir / name, surfaces[si], name, alpha));
    }
  write_gallery(dir, members);
  return seconds_since(t0);
}

}  // namespace cmcsurf
