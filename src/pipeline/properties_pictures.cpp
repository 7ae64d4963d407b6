#include "pipeline/properties_pictures.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "common/wall_clock.h"
#include "mesh/tri_mesh.h"  // dot
#include "properties/cell_properties.h"
#include "properties/directional_modulus.h"
#include "properties/power_law_fit.h"
#include "render/colormap.h"
#include "render/raster.h"
#include "render/plot.h"
#include "render/text.h"

namespace cmcsurf {

namespace {

using properties::Matrix6;
using properties::Vector3;

constexpr Rgb kInk{0.1f, 0.1f, 0.12f};
constexpr Rgb kGreyInk{0.38f, 0.38f, 0.4f};
constexpr Rgb kGrid{0.92f, 0.92f, 0.93f};
constexpr Rgb kBound{0.35f, 0.35f, 0.38f};
constexpr int kSupersample = 2;

// The oblique view of preview.png (azimuth 30, elevation 24 degrees, z up), orthographic.
struct View {
  Vector3 right, up, toward;
  View() {
    const double az = 30.0 * M_PI / 180.0, el = 24.0 * M_PI / 180.0;
    toward = {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
    right = {-std::sin(az), std::cos(az), 0.0};
    up = {-std::sin(el) * std::cos(az), -std::sin(el) * std::sin(az), std::cos(el)};
  }
};

// A direction as [a, b, c] to two decimals, its largest component positive (E(d) = E(-d)).
std::string direction_text(Vector3 d) {
  int big = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(d[a]) > std::abs(d[big]) + 1e-9) big = a;
  if (d[big] < 0) d = {-d[0], -d[1], -d[2]};
  auto c = [](double v) { return std::abs(v) < 5e-3 ? 0.0 : v; };
  return fmt::format("[{:.2f} {:.2f} {:.2f}]", c(d[0]), c(d[1]), c(d[2]));
}

void draw_color_bar(Image& img, int x, int y, int width, int height, double lo, double hi,
                    const std::string& caption) {
  draw_text(img, x, y - 14, 15, caption, kInk);
  for (int j = 0; j < height; ++j)
    img.fill_rect(x, y + j, width, 1, diverging(1.0 - (j + 0.5) / height));
  img.fill_rect(x - 1, y - 1, width + 2, 1, kGreyInk);
  img.fill_rect(x - 1, y + height, width + 2, 1, kGreyInk);
  img.fill_rect(x - 1, y - 1, 1, height + 2, kGreyInk);
  img.fill_rect(x + width, y - 1, 1, height + 2, kGreyInk);
  for (int k = 0; k <= 4; ++k) {
    const double t = 1.0 - k / 4.0;
    const int ty = y + int(std::lround(k / 4.0 * (height - 1)));
    img.fill_rect(x + width, ty, 6, 1, kInk);
    draw_text(img, x + width + 9, ty + 5, 14, fmt::format("{:.4g}", lo + t * (hi - lo)), kInk);
  }
}

}  // namespace

PropertiesPicture youngs_modulus_picture(const nlohmann::json& p, const std::string& title) {
  const auto t0 = WallClock::now();
  PropertiesPicture out;
  if (!p.contains("stiffness_voigt")) return out;
  Matrix6 c{};
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) c[i][j] = p["stiffness_voigt"][i][j].get<double>();
  const properties::ElasticConstants e = properties::elastic_constants(c);
  const properties::DirectionalSurface s =
      properties::directional_youngs_surface(e.compliance_voigt, 48);
  const auto [lo_it, hi_it] = std::minmax_element(s.modulus.begin(), s.modulus.end());
  const double lo = std::min(*lo_it, e.youngs_modulus_min),
               hi = std::max(*hi_it, e.youngs_modulus_max);
  if (!(hi > 0.0)) return out;  // no stiffness in any direction: nothing to draw

  const int panel = 600, bar = 180, head = 78, foot = 64;
  Image img(panel + bar, head + panel + foot);
  const View view;
  const double px = panel * kSupersample, zoom = 0.38 * px / hi;
  auto project = [&](const Vector3& q) {
    return std::array<float, 3>{float(0.5 * px + zoom * dot(q, view.right)),
                                float(0.5 * px - zoom * dot(q, view.up)),
                                float(dot(q, view.toward))};
  };
  Canvas canvas(panel, panel, kSupersample, {1, 1, 1});
  std::vector<ScreenVertex> v(s.directions.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    const double m = s.modulus[i];
    const auto& d = s.directions[i];
    const auto xyz = project({m * d[0], m * d[1], m * d[2]});
    const auto& n = s.normals[i];
    v[i] = {xyz[0], xyz[1], xyz[2],
            diverging(hi > lo * (1 + 1e-9) ? (m - lo) / (hi - lo) : 0.5),
            float(dot(n, view.right)), float(-dot(n, view.up)), float(dot(n, view.toward))};
  }
  canvas.draw_triangles(v, s.triangles);
  const double reach = 1.22 * hi;
  for (int a = 0; a < 3; ++a) {  // the axes through the cell, hidden where inside the surface
    Vector3 q0{}, q1{};
    q0[a] = -reach;
    q1[a] = reach;
    const auto p0 = project(q0), p1 = project(q1);
    canvas.draw_line(p0[0], p0[1], p0[2], p1[0], p1[1], p1[2], kGreyInk);
  }
  img.paste(canvas.resolve(), 0, head);
  for (int a = 0; a < 3; ++a) {
    Vector3 q{};
    q[a] = 1.3 * hi;
    const auto p = project(q);
    draw_text(img, int(p[0] / kSupersample), head + int(p[1] / kSupersample) + 5, 17,
              std::string(1, "xyz"[a]), kInk, Align::kCenter);
  }
  draw_text(img, (panel + bar) / 2, 30, 18, title, kInk, Align::kCenter);
  draw_text(img, (panel + bar) / 2, 56, 14,
            "directional Young's modulus: the surface r = E(d) d over unit directions d",
            kGreyInk, Align::kCenter);
  draw_color_bar(img, panel + 28, head + 70, 26, panel - 180, lo, hi, "E(d) / E_s");
  draw_text(img, 24, head + panel + 24, 15,
            fmt::format("E min {:.4g} along {}    E max {:.4g} along {}    max / min {:.3g}",
                        e.youngs_modulus_min, direction_text(e.direction_min),
                        e.youngs_modulus_max, direction_text(e.direction_max),
                        e.youngs_modulus_min > 0 ? e.youngs_modulus_max / e.youngs_modulus_min
                                                 : INFINITY),
            kInk);
  draw_text(img, 24, head + panel + 48, 14,
            fmt::format("Zener ratio 2 C44 / (C11 - C12) = {:.3g}; an isotropic solid is a "
                        "sphere", e.zener_ratio),
            kGreyInk);
  out.image = std::move(img);
  out.seconds = seconds_since(t0);
  return out;
}

namespace {

struct Point {
  double rho, value, error;  // error NaN: none
};
// Permeability against porosity, with the specific surface S (per cell size) that the
// Kozeny-Carman line needs (NaN: none).
struct FlowPoint {
  double porosity, k, error, surface;
};
struct Series {
  std::string surface, solid, part;  // part: cmc or nodal
  double poisson_ratio = 0.3;
  std::vector<Point> youngs, conductivity;
  std::vector<FlowPoint> flow;
  double kozeny_carman = NAN;  // the fitted c of k = eps^3 / (c S^2)
};

double number_or_nan(const nlohmann::json& j, const std::string& key) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : NAN;
}

// The tick values of a log axis over [lo, hi]: 1, 2, 3, 4, 5, 6, 8 times powers of ten within a
// decade (a sweep's densities), 1, 2, 5 within two and a half, else 1.
std::vector<double> log_ticks(double lo, double hi) {
  std::vector<double> t;
  const double decades = std::log10(hi / lo);
  const std::vector<double> mantissas = decades < 1.0   ? std::vector<double>{1, 2, 3, 4, 5, 6, 8}
                                        : decades < 2.5 ? std::vector<double>{1, 2, 5}
                                                        : std::vector<double>{1};
  for (int k = int(std::floor(std::log10(lo))); k <= int(std::ceil(std::log10(hi))); ++k)
    for (double m : mantissas) {
      const double v = m * std::pow(10.0, k);
      if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9)) t.push_back(v);
    }
  return t;
}

const Rgb kFamilyColors[] = {{0.12f, 0.38f, 0.72f}, {0.80f, 0.33f, 0.10f}, {0.13f, 0.58f, 0.30f},
                             {0.55f, 0.25f, 0.65f}, {0.72f, 0.60f, 0.05f}, {0.10f, 0.60f, 0.65f},
                             {0.85f, 0.20f, 0.45f}, {0.40f, 0.40f, 0.42f}};

// A log-log panel: pixel box [x0, x1] x [y0, y1] over the ranges [x_lo, x_hi], [y_lo, y_hi].
struct LogFrame {
  int x0, x1, y0, y1;
  double x_lo, x_hi, y_lo, y_hi;
  double sx(double v) const { return x0 + (x1 - x0) * std::log(v / x_lo) / std::log(x_hi / x_lo); }
  double sy(double v) const {
    const double l = std::clamp(std::log(std::max(v, 1e-300) / y_lo), -1.0,
                                std::log(y_hi / y_lo) + 1.0);
    return y1 - (y1 - y0) * l / std::log(y_hi / y_lo);
  }
};

// The panel's grid, ticks, frame and axis labels.
void draw_frame(Image& img, const LogFrame& f, const std::string& x_label,
                const std::string& y_label) {
  for (double t : log_ticks(f.x_lo, f.x_hi)) {
    const int x = int(std::lround(f.sx(t)));
    img.fill_rect(x, f.y0, 1, f.y1 - f.y0, kGrid);
    img.fill_rect(x, f.y1, 1, 6, kInk);
    draw_text(img, x, f.y1 + 22, 13, fmt::format("{:g}", t), kInk, Align::kCenter);
  }
  for (double t : log_ticks(f.y_lo, f.y_hi)) {
    const int y = int(std::lround(f.sy(t)));
    img.fill_rect(f.x0, y, f.x1 - f.x0, 1, kGrid);
    img.fill_rect(f.x0 - 6, y, 6, 1, kInk);
    draw_text(img, f.x0 - 9, y + 5, 13, fmt::format("{:g}", t), kInk, Align::kRight);
  }
  img.fill_rect(f.x0, f.y0, 1, f.y1 - f.y0 + 1, kInk);
  img.fill_rect(f.x0, f.y1, f.x1 - f.x0 + 1, 1, kInk);
  img.fill_rect(f.x0, f.y0, f.x1 - f.x0 + 1, 1, kGreyInk);
  img.fill_rect(f.x1, f.y0, 1, f.y1 - f.y0 + 1, kGreyInk);
  draw_text(img, (f.x0 + f.x1) / 2, f.y1 + 46, 15, x_label, kInk, Align::kCenter);
  draw_text(img, f.x0, f.y0 - 8, 15, y_label, kInk);
}

// A vertical error bar of +-error around v at x.
void draw_error_bar(Image& img, const LogFrame& f, double x, double v, double error, Rgb c) {
  const double ya = f.sy(v + error), yb = f.sy(std::max(v - error, f.y_lo));
  draw_line(img, x, ya, x, yb, c);
  draw_line(img, x - 4, ya, x + 4, ya, c);
  draw_line(img, x - 4, yb, x + 4, yb, c);
}

std::string fit_text(const nlohmann::json& f) {
  if (!f.value("valid", false)) return "no fit (one density)";
  return fmt::format("{:.3g} ρ^{:.3g}", f["coefficient"].get<double>(),
                     f["exponent"].get<double>());
}

}  // namespace

PropertiesChart properties_chart(const std::vector<nlohmann::json>& reports,
                                 const std::string& title) {
  const auto t0 = WallClock::now();
  PropertiesChart out;
  // Series per (surface, solid, part), in the order the members come.
  std::vector<Series> series;
  auto series_of = [&](const std::string& surface, const std::string& solid,
                       const std::string& part) -> Series& {
    for (Series& s : series)
      if (s.surface == surface && s.solid == solid && s.part == part) return s;
    series.push_back({surface, solid, part, 0.3, {}, {}, {}, NAN});
    return series.back();
  };
  for (const nlohmann::json& r : reports) {
    if (!r.contains("properties") || !r["properties"].is_object()) continue;
    const nlohmann::json& p = r["properties"];
    const std::string surface = r.value("surface", std::string("?"));
    const std::string solid = p.value("solid", std::string("network"));
    const double nu = p.contains("material") ? p["material"].value("poisson_ratio", 0.3) : 0.3;
    // A member's point, or with a ramp of sheet porosities one point per porosity.
    const bool ramp = r.contains("properties_ramp") && r["properties_ramp"].is_array();
    for (const nlohmann::json& point : ramp ? r["properties_ramp"] : nlohmann::json::array({r}))
      for (const std::string part : {"cmc", "nodal"}) {
        const std::string prefix = part == "cmc" ? "properties_" : "properties_nodal_";
        const double rho = number_or_nan(point, prefix + "relative_density");
        if (!std::isfinite(rho)) continue;
        Series& s = series_of(surface, solid, part);
        s.poisson_ratio = nu;
        const double e = number_or_nan(point, prefix + "youngs_modulus"),
                     k = number_or_nan(point, prefix + "conductivity_solid");
        if (std::isfinite(e))
          s.youngs.push_back({rho, e, number_or_nan(point, prefix + "youngs_modulus_error")});
        if (std::isfinite(k))
          s.conductivity.push_back(
              {rho, k, number_or_nan(point, prefix + "conductivity_solid_error")});
        const double perm = number_or_nan(point, prefix + "permeability");
        if (perm > 0.0)
          s.flow.push_back({1.0 - rho, perm, number_or_nan(point, prefix + "permeability_error"),
                            number_or_nan(point, prefix + "specific_surface")});
      }
  }
  if (series.empty()) return out;
  for (Series& s : series)
    for (auto* pts : {&s.youngs, &s.conductivity})
      std::sort(pts->begin(), pts->end(),
                [](const Point& a, const Point& b) { return a.rho < b.rho; });
  for (Series& s : series)
    std::sort(s.flow.begin(), s.flow.end(),
              [](const FlowPoint& a, const FlowPoint& b) { return a.porosity < b.porosity; });

  // The fits (Gibson-Ashby: y = C rho^n).
  std::map<std::tuple<std::string, std::string, std::string, std::string>, nlohmann::json> fit_of;
  for (const Series& s : series)
    for (const auto& [quantity, pts] :
         {std::pair<std::string, const std::vector<Point>*>{"youngs_modulus", &s.youngs},
          {"conductivity_solid", &s.conductivity}}) {
      std::vector<double> rho, y;
      for (const Point& q : *pts) rho.push_back(q.rho), y.push_back(q.value);
      const properties::PowerLawFit f = properties::fit_power_law(rho, y);
      nlohmann::json j = {{"surface", s.surface}, {"solid", s.solid},     {"part", s.part},
                          {"quantity", quantity}, {"points", f.points}, {"valid", f.valid}};
      if (f.valid) {
        j["coefficient"] = f.coefficient;
        j["exponent"] = f.exponent;
        j["rms_log_residual"] = f.rms_log_residual;
      }
      fit_of[{s.surface, s.solid, s.part, quantity}] = j;
      out.fits.push_back(j);
    }
  // Kozeny-Carman, k = eps^3 / (c S^2) (S per cell volume), per family and part: the c whose
  // line fits log k best is the geometric mean of the members' eps^3 / (k S^2).
  bool any_flow = false;
  for (Series& s : series) {
    if (s.flow.empty()) continue;
    any_flow = true;
    std::vector<double> log_c;
    for (const FlowPoint& q : s.flow)
      if (q.surface > 0.0) log_c.push_back(std::log(std::pow(q.porosity, 3) /
                                                    (q.k * q.surface * q.surface)));
    nlohmann::json j = {{"surface", s.surface},
                        {"solid", s.solid},
                        {"part", s.part},
                        {"quantity", "kozeny_carman_constant"},
                        {"points", log_c.size()},
                        {"valid", !log_c.empty()}};
    if (!log_c.empty()) {
      double mean = 0.0, rms = 0.0;
      for (double v : log_c) mean += v / double(log_c.size());
      for (double v : log_c) rms += (v - mean) * (v - mean) / double(log_c.size());
      s.kozeny_carman = std::exp(mean);
      j["coefficient"] = s.kozeny_carman;
      j["rms_log_residual"] = std::sqrt(rms);
    }
    out.fits.push_back(j);
  }

  // The x range: every density, with a margin; the bound is drawn over it.
  double x_lo = INFINITY, x_hi = 0.0;
  for (const Series& s : series)
    for (const auto* pts : {&s.youngs, &s.conductivity})
      for (const Point& q : *pts) x_lo = std::min(x_lo, q.rho), x_hi = std::max(x_hi, q.rho);
  x_lo /= 1.25;
  x_hi = std::min(1.0, x_hi * 1.25);
  if (!(x_hi > x_lo * 1.5)) x_lo = x_hi / 1.5;

  // Families in order: one colour each; a legend row per (surface, solid).
  std::vector<std::pair<std::string, std::string>> groups;
  for (const Series& s : series)
    if (std::find(groups.begin(), groups.end(), std::pair{s.surface, s.solid}) == groups.end())
      groups.push_back({s.surface, s.solid});
  auto color_of = [&](const Series& s) {
    const auto it = std::find(groups.begin(), groups.end(), std::pair{s.surface, s.solid});
    return kFamilyColors[std::size_t(it - groups.begin()) % std::size(kFamilyColors)];
  };
  bool any_nodal = false;
  for (const Series& s : series) any_nodal = any_nodal || s.part == "nodal";

  const int plot_w = 470, plot_h = 400, left = 78, gap = 110, top = 84;
  const int panels = any_flow ? 3 : 2;
  const int legend_rows = int(groups.size()) * (any_nodal ? 2 : 1) + 1;
  const int width = 24 + left + (panels - 1) * (plot_w + gap) + plot_w + 30;
  const int height = top + plot_h + 70 + 22 * legend_rows + 20;
  Image img(width, height);
  draw_text(img, width / 2, 32, 18, title, kInk, Align::kCenter);
  draw_text(img, width / 2, 58, 14,
            any_flow ? "log-log; solid lines: CMC; dashed: nodal; dotted: Hashin-Shtrikman upper "
                       "bound, Kozeny-Carman (k); bars: grid-check error"
                     : "log-log; solid lines: CMC; dashed: nodal; dotted: Hashin-Shtrikman "
                       "upper bound; bars: grid-check error",
            kGreyInk, Align::kCenter);

  const double nu = series.front().poisson_ratio;
  for (int panel = 0; panel < 2; ++panel) {
    const bool youngs = panel == 0;
    const int x0 = 24 + left + panel * (plot_w + gap), x1 = x0 + plot_w, y0 = top,
              y1 = top + plot_h;
    auto bound = [&](double rho) {
      const auto b = properties::hashin_shtrikman_upper(rho, nu);
      return youngs ? b.youngs_modulus : b.conductivity;
    };
    double y_lo = INFINITY, y_hi = bound(x_hi);
    for (const Series& s : series)
      for (const Point& q : youngs ? s.youngs : s.conductivity) {
        const double e = std::isfinite(q.error) ? q.error : 0.0;
        if (q.value - e > 0) y_lo = std::min(y_lo, q.value - e);
        else if (q.value > 0) y_lo = std::min(y_lo, q.value);
        y_hi = std::max(y_hi, q.value + e);
      }
    if (!std::isfinite(y_lo)) y_lo = bound(x_lo);
    y_lo /= 1.4;
    y_hi *= 1.3;
    const LogFrame f{x0, x1, y0, y1, x_lo, x_hi, y_lo, y_hi};
    auto sx = [&](double rho) { return f.sx(rho); };
    auto sy = [&](double v) { return f.sy(v); };
    draw_frame(img, f, "relative density ρ",
               youngs ? "E / E_s (mean of x, y, z)" : "k_solid / k_s (mean diagonal)");
    // The bound, dotted.
    double phase = 0.0;
    for (int i = 0; i < 80; ++i) {
      const double r0 = x_lo * std::pow(x_hi / x_lo, i / 80.0),
                   r1 = x_lo * std::pow(x_hi / x_lo, (i + 1) / 80.0);
      draw_line(img, sx(r0), sy(bound(r0)), sx(r1), sy(bound(r1)), kBound, 2.0, 4.0, &phase);
    }
    for (const Series& s : series) {
      const auto& pts = youngs ? s.youngs : s.conductivity;
      const Rgb c = color_of(s);
      const bool dashed = s.part == "nodal";
      phase = 0.0;
      for (std::size_t i = 1; i < pts.size(); ++i)
        if (pts[i - 1].value > 0 && pts[i].value > 0)
          draw_line(img, sx(pts[i - 1].rho), sy(pts[i - 1].value), sx(pts[i].rho),
                    sy(pts[i].value), c, dashed ? 9.0 : 0.0, dashed ? 6.0 : 0.0, &phase,
                    dashed ? 1.0f : 1.4f);
      for (const Point& q : pts) {
        if (!(q.value > 0)) continue;
        const double x = sx(q.rho), y = sy(q.value);
        if (std::isfinite(q.error) && q.error > 0) {
          draw_error_bar(img, f, x, q.value, q.error, c);
          out.error_bars.push_back({{"surface", s.surface},
                                    {"solid", s.solid},
                                    {"part", s.part},
                                    {"quantity", youngs ? "youngs_modulus" : "conductivity_solid"},
                                    {"relative_density", q.rho},
                                    {"value", q.value},
                                    {"error", q.error}});
        }
        draw_disc(img, x, y, 3.5, c, !dashed);
      }
    }
  }
  // Permeability (mean diagonal, cell-size^2) against porosity, with each series'
  // Kozeny-Carman line through its members' specific surfaces, dotted.
  if (any_flow) {
    const int x0 = 24 + left + 2 * (plot_w + gap), x1 = x0 + plot_w, y0 = top, y1 = top + plot_h;
    double p_lo = INFINITY, p_hi = 0.0, y_lo = INFINITY, y_hi = 0.0;
    for (const Series& s : series)
      for (const FlowPoint& q : s.flow) {
        p_lo = std::min(p_lo, q.porosity);
        p_hi = std::max(p_hi, q.porosity);
        const double e = std::isfinite(q.error) ? q.error : 0.0;
        y_lo = std::min(y_lo, q.k - e > 0 ? q.k - e : q.k);
        y_hi = std::max(y_hi, q.k + e);
        if (q.surface > 0.0 && std::isfinite(s.kozeny_carman)) {
          const double kc = std::pow(q.porosity, 3) / (s.kozeny_carman * q.surface * q.surface);
          y_lo = std::min(y_lo, kc);
          y_hi = std::max(y_hi, kc);
        }
      }
    p_lo /= 1.1;
    p_hi = std::min(1.0, p_hi * 1.05);
    if (!(p_hi > p_lo * 1.2)) p_lo = p_hi / 1.2;
    y_lo /= 1.4;
    y_hi *= 1.3;
    if (!(y_hi > y_lo * 10)) y_lo = y_hi / 10;
    const LogFrame f{x0, x1, y0, y1, p_lo, p_hi, y_lo, y_hi};
    draw_frame(img, f, "porosity ε = 1 - ρ", "k / cell size² (mean diagonal)");
    for (const Series& s : series) {
      const Rgb c = color_of(s);
      const bool dashed = s.part == "nodal";
      double phase = 0.0, kc_phase = 0.0;
      for (std::size_t i = 0; i < s.flow.size(); ++i) {
        const FlowPoint& q = s.flow[i];
        const double x = f.sx(q.porosity);
        if (i > 0) {
          const FlowPoint& a = s.flow[i - 1];
          draw_line(img, f.sx(a.porosity), f.sy(a.k), x, f.sy(q.k), c, dashed ? 9.0 : 0.0,
                    dashed ? 6.0 : 0.0, &phase, dashed ? 1.0f : 1.4f);
          if (a.surface > 0.0 && q.surface > 0.0 && std::isfinite(s.kozeny_carman) &&
              s.part == "cmc") {
            auto kc = [&](const FlowPoint& p) {
              return std::pow(p.porosity, 3) / (s.kozeny_carman * p.surface * p.surface);
            };
            draw_line(img, f.sx(a.porosity), f.sy(kc(a)), x, f.sy(kc(q)), c, 2.0, 4.0,
                      &kc_phase);
          }
        }
        if (std::isfinite(q.error) && q.error > 0) {
          draw_error_bar(img, f, x, q.k, q.error, c);
          out.error_bars.push_back({{"surface", s.surface},
                                    {"solid", s.solid},
                                    {"part", s.part},
                                    {"quantity", "permeability"},
                                    {"porosity", q.porosity},
                                    {"value", q.k},
                                    {"error", q.error}});
        }
        draw_disc(img, x, f.sy(q.k), 3.5, c, !dashed);
      }
    }
  }
  // The legend: per family and solid, the fits of each part.
  int y = top + plot_h + 86;
  for (const Series& s : series) {
    const Rgb c = color_of(s);
    const double x = 30;
    double phase = 0.0;
    draw_line(img, x, y - 5, x + 34, y - 5, c, s.part == "nodal" ? 9.0 : 0.0,
              s.part == "nodal" ? 6.0 : 0.0, &phase);
    draw_disc(img, x + 17, y - 5, 3.5, c, s.part != "nodal");
    draw_text(img, int(x) + 44, y, 14,
              fmt::format("{} {} {}:  E / E_s = {}   k / k_s = {}{}", s.surface, s.solid,
                          s.part == "cmc" ? "CMC" : "nodal",
                          fit_text(fit_of[{s.surface, s.solid, s.part, "youngs_modulus"}]),
                          fit_text(fit_of[{s.surface, s.solid, s.part, "conductivity_solid"}]),
                          std::isfinite(s.kozeny_carman)
                              ? fmt::format("   Kozeny-Carman c = {:.3g}", s.kozeny_carman)
                              : std::string()),
              kInk);
    y += 22;
  }
  {
    double phase = 0.0;
    draw_line(img, 30, y - 5, 64, y - 5, kBound, 2.0, 4.0, &phase);
    draw_text(img, 74, y, 14,
              fmt::format("Hashin-Shtrikman upper bound (ν_s = {:g}); fits: least squares of "
                          "log y on log ρ (Gibson-Ashby C ρ^n){}",
                          nu,
                          any_flow ? "; Kozeny-Carman k = ε³ / (c S²), S per cell volume "
                                     "(c: geometric mean over the members)"
                                   : ""),
              kInk);
  }
  out.image = std::move(img);
  out.seconds = seconds_since(t0);
  return out;
}

}  // namespace cmcsurf
