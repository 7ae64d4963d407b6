#include "driver/families_figure.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>

#include "common/wall_clock.h"
#include "common/atomic_file.h"
#include "io/png.h"
#include "report/report_html.h"
#include "measure/literature.h"
#include "render/plot.h"
#include "render/text.h"

namespace cmcsurf {

namespace {

constexpr Rgb kInk{0.1f, 0.1f, 0.12f};
constexpr Rgb kGreyInk{0.38f, 0.38f, 0.4f};
constexpr Rgb kGrid{0.92f, 0.92f, 0.93f};
constexpr Rgb kProfile{0.45f, 0.45f, 0.47f};
const Rgb kColors[] = {{0.12f, 0.38f, 0.72f}, {0.80f, 0.33f, 0.10f}, {0.13f, 0.58f, 0.30f},
                       {0.55f, 0.25f, 0.65f}, {0.72f, 0.60f, 0.05f}, {0.10f, 0.60f, 0.65f},
                       {0.85f, 0.20f, 0.45f}, {0.40f, 0.40f, 0.42f}};

double number(const nlohmann::json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && it->is_number() ? it->get<double>() : NAN;
}

struct Point {
  double alpha, area, area_error, h, h_error, area_diffuse, h_diffuse;
};

struct Family {
  std::string surface;
  std::vector<Point> points;
  nlohmann::json cell;  // the first member's crystallographic_cell (null: none)
};

// A linear panel: pixel box [x0, x1] x [y0, y1] over [x_lo, x_hi] x [y_lo, y_hi].
struct Frame {
  int x0, x1, y0, y1;
  double x_lo, x_hi, y_lo, y_hi;
  double sx(double v) const { return x0 + (x1 - x0) * (v - x_lo) / (x_hi - x_lo); }
  double sy(double v) const { return y1 - (y1 - y0) * (v - y_lo) / (y_hi - y_lo); }
};

// A tick step of 1, 2 or 5 times a power of ten giving 4 to 10 ticks over [lo, hi].
double tick_step(double lo, double hi) {
  const double span = hi - lo, p = std::pow(10.0, std::floor(std::log10(span)));
  for (double m : {0.1, 0.2, 0.5, 1.0, 2.0, 5.0})
    if (span / (m * p) <= 10.0) return m * p;
  return 10.0 * p;
}

// The range of values with their bars, widened by 6 % each side (a flat one by 0.05).
std::pair<double, double> padded(double lo, double hi) {
  const double pad = hi > lo ? 0.06 * (hi - lo) : 0.05;
  return {lo - pad, hi + pad};
}

void draw_frame(Image& img, const Frame& f, const std::string& x_label,
                const std::string& y_label) {
  const double xs = tick_step(f.x_lo, f.x_hi), ys = tick_step(f.y_lo, f.y_hi);
  for (double t = std::ceil(f.x_lo / xs - 1e-9) * xs; t <= f.x_hi + 1e-12; t += xs) {
    const int x = int(std::lround(f.sx(t)));
    img.fill_rect(x, f.y0, 1, f.y1 - f.y0, kGrid);
    img.fill_rect(x, f.y1, 1, 6, kInk);
    draw_text(img, x, f.y1 + 22, 13, fmt::format("{:g}", std::abs(t) < 1e-12 ? 0.0 : t), kInk,
              Align::kCenter);
  }
  for (double t = std::ceil(f.y_lo / ys - 1e-9) * ys; t <= f.y_hi + 1e-12; t += ys) {
    const int y = int(std::lround(f.sy(t)));
    img.fill_rect(f.x0, y, f.x1 - f.x0, 1, kGrid);
    img.fill_rect(f.x0 - 6, y, 6, 1, kInk);
    draw_text(img, f.x0 - 9, y + 5, 13, fmt::format("{:g}", std::abs(t) < 1e-12 ? 0.0 : t), kInk,
              Align::kRight);
  }
  img.fill_rect(f.x0, f.y0, 1, f.y1 - f.y0 + 1, kInk);
  img.fill_rect(f.x0, f.y1, f.x1 - f.x0 + 1, 1, kInk);
  img.fill_rect(f.x0, f.y0, f.x1 - f.x0 + 1, 1, kGreyInk);
  img.fill_rect(f.x1, f.y0, 1, f.y1 - f.y0 + 1, kGreyInk);
  draw_text(img, (f.x0 + f.x1) / 2, f.y1 + 46, 15, x_label, kInk, Align::kCenter);
  draw_text(img, f.x0, f.y0 - 10, 15, y_label, kInk);
}

// A vertical error bar of +-error around v at x, with caps; returns its ends' pixel rows.
std::pair<double, double> draw_error_bar(Image& img, const Frame& f, double x, double v,
                                         double error, Rgb c) {
  const double ya = f.sy(v + error), yb = f.sy(v - error);
  draw_line(img, x, ya, x, yb, c, 0, 0, nullptr, 1.3f);
  draw_line(img, x - 4, ya, x + 4, ya, c);
  draw_line(img, x - 4, yb, x + 4, yb, c);
  return {ya, yb};
}

// How a family's numbers per computed cell convert to its crystallographic cell's.
std::string cell_text(const Family& fam) {
  const nlohmann::json& c = fam.cell;
  const int n = c.value("cells_per_computed_cell", 1);
  const double r = c.value("lattice_parameter", 1.0);
  const std::string group = c.value("space_group", std::string("?"));
  if (n == 1) return fmt::format("{}: the computed cell is the {} cell", fam.surface, group);
  return fmt::format("{}: the computed cell holds {} {} cells (a_c = {:g} a): A_c / a_c^2 = "
                     "A / {:g}, H a_c = {:g} H",
                     fam.surface, n, group, r, n * r * r, r);
}

}  // namespace

FamiliesFigure families_figure(const std::vector<nlohmann::json>& reports,
                               const FamiliesFigureOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  FamiliesFigure out;
  std::vector<Family> families;
  for (const nlohmann::json& r : reports) {
    Point p{number(r, "volume_fraction_target"), number(r, "area"), number(r, "area_error"),
            number(r, "mean_curvature"), number(r, "mean_curvature_error"),
            number(r, "area_diffuse"), number(r, "mean_curvature_diffuse")};
    if (!std::isfinite(p.alpha)) p.alpha = number(r, "volume_fraction");
    if (!std::isfinite(p.alpha) || !std::isfinite(p.area) || !std::isfinite(p.h)) continue;
    for (double* e : {&p.area_error, &p.h_error})
      if (!std::isfinite(*e) || *e < 0) *e = 0.0;
    const std::string surface = r.value("surface", std::string("?"));
    auto it = std::find_if(families.begin(), families.end(),
                           [&](const Family& f) { return f.surface == surface; });
    if (it == families.end()) {
      families.push_back({surface, {}, r.value("crystallographic_cell", nlohmann::json())});
      it = families.end() - 1;
    }
    it->points.push_back(p);
  }
  if (families.empty()) return out;
  for (Family& f : families)
    std::sort(f.points.begin(), f.points.end(),
              [](const Point& a, const Point& b) { return a.alpha < b.alpha; });

  // Ranges over the values, their bars, the diffuse values drawn and the literature marks.
  double a_lo = 1.0, a_hi = 0.0, h_lo = INFINITY, h_hi = -INFINITY, A_lo = INFINITY,
         A_hi = -INFINITY;
  for (const Family& f : families)
    for (const Point& p : f.points) {
      a_lo = std::min(a_lo, p.alpha);
      a_hi = std::max(a_hi, p.alpha);
      h_lo = std::min(h_lo, p.h - p.h_error);
      h_hi = std::max(h_hi, p.h + p.h_error);
      A_lo = std::min(A_lo, p.area - p.area_error);
      A_hi = std::max(A_hi, p.area + p.area_error);
      if (options.diffuse && std::isfinite(p.h_diffuse) && std::isfinite(p.area_diffuse)) {
        h_lo = std::min(h_lo, p.h_diffuse);
        h_hi = std::max(h_hi, p.h_diffuse);
        A_lo = std::min(A_lo, p.area_diffuse);
        A_hi = std::max(A_hi, p.area_diffuse);
      }
    }
  const auto [x_lo, x_hi] = a_hi > a_lo ? std::pair{a_lo - 0.03, a_hi + 0.03}
                                        : std::pair{a_lo - 0.1, a_hi + 0.1};
  for (const Family& f : families)
    if (const auto a = minimal_surface_area(f.surface); a && 0.5 >= x_lo && 0.5 <= x_hi) {
      A_lo = std::min(A_lo, *a);
      A_hi = std::max(A_hi, *a);
    }
  const auto [hy_lo, hy_hi] = padded(h_lo, h_hi);
  const auto [ay_lo, ay_hi] = padded(A_lo, A_hi);

  const int width = 1200, panel_w = 480, panel_h = 360, top = 90;
  int captions = 0;
  for (const Family& f : families) captions += f.cell.is_object() ? 1 : 0;
  const int legend_y = top + panel_h + 80;
  const int height = legend_y + 24 * int(families.size() + 2 + captions) + 10;
  Image img(width, height);
  draw_text(img, width / 2, 32, 18,
            options.title.empty() ? "Families of CMC surfaces (Fig. 11)" : options.title, kInk,
            Align::kCenter);
  draw_text(img, width / 2, 58, 14,
            "sharp values with their error estimates (Richardson, report keys area_error and "
            "mean_curvature_error)",
            kGreyInk, Align::kCenter);
  const Frame fh{90, 90 + panel_w, top, top + panel_h, x_lo, x_hi, hy_lo, hy_hi};
  const Frame fa{width - 40 - panel_w, width - 40, top, top + panel_h, x_lo, x_hi, ay_lo, ay_hi};
  draw_frame(img, fh, "volume fraction alpha",
             "(a) mean curvature H a per computed cell (a = 1)");
  draw_frame(img, fa, "volume fraction alpha", "(b) area A per computed cell (a = 1)");

  // I_scp(min(alpha, 1 - alpha)), dashed, behind the families.
  double phase = 0.0;
  const int samples = 200;
  for (int i = 0; i < samples; ++i) {
    const double u0 = x_lo + (x_hi - x_lo) * i / samples,
                 u1 = x_lo + (x_hi - x_lo) * (i + 1) / samples;
    const double v0 = i_scp_of_fraction(std::clamp(u0, 1e-6, 1 - 1e-6)),
                 v1 = i_scp_of_fraction(std::clamp(u1, 1e-6, 1 - 1e-6));
    if (v0 < ay_lo || v0 > ay_hi || v1 < ay_lo || v1 > ay_hi) {
      phase = 0.0;
      continue;
    }
    draw_line(img, fa.sx(u0), fa.sy(v0), fa.sx(u1), fa.sy(v1), kProfile, 6.0, 4.0, &phase);
  }
  for (std::size_t k = 0; k < families.size(); ++k) {
    const Family& f = families[k];
    const Rgb c = kColors[k % std::size(kColors)];
    for (std::size_t i = 1; i < f.points.size(); ++i) {
      const Point &p = f.points[i - 1], &q = f.points[i];
      draw_line(img, fh.sx(p.alpha), fh.sy(p.h), fh.sx(q.alpha), fh.sy(q.h), c);
      draw_line(img, fa.sx(p.alpha), fa.sy(p.area), fa.sx(q.alpha), fa.sy(q.area), c);
      if (options.diffuse && std::isfinite(p.h_diffuse) && std::isfinite(q.h_diffuse)) {
        double ph = 0.0, pa = 0.0;
        draw_line(img, fh.sx(p.alpha), fh.sy(p.h_diffuse), fh.sx(q.alpha), fh.sy(q.h_diffuse),
                  c, 2.0, 3.0, &ph);
        draw_line(img, fa.sx(p.alpha), fa.sy(p.area_diffuse), fa.sx(q.alpha),
                  fa.sy(q.area_diffuse), c, 2.0, 3.0, &pa);
      }
    }
    for (const Point& p : f.points) {
      const double x = fh.sx(p.alpha), xa = fa.sx(p.alpha);
      const auto bh = draw_error_bar(img, fh, x, p.h, p.h_error, c);
      const auto ba = draw_error_bar(img, fa, xa, p.area, p.area_error, c);
      draw_disc(img, x, fh.sy(p.h), 3.5, c, true);
      draw_disc(img, xa, fa.sy(p.area), 3.5, c, true);
      if (options.diffuse && std::isfinite(p.h_diffuse) && std::isfinite(p.area_diffuse)) {
        draw_disc(img, x, fh.sy(p.h_diffuse), 3.0, c, false);
        draw_disc(img, xa, fa.sy(p.area_diffuse), 3.0, c, false);
      }
      out.points.push_back({{"surface", f.surface},
                            {"volume_fraction", p.alpha},
                            {"area", p.area},
                            {"area_error", p.area_error},
                            {"mean_curvature", p.h},
                            {"mean_curvature_error", p.h_error},
                            {"x", x},
                            {"x_area", xa},
                            {"y_mean_curvature", fh.sy(p.h)},
                            {"y_mean_curvature_bar", {bh.first, bh.second}},
                            {"y_area", fa.sy(p.area)},
                            {"y_area_bar", {ba.first, ba.second}}});
    }
    // The literature area of the minimal surface at alpha = 1/2: a cross.
    if (const auto a = minimal_surface_area(f.surface); a && 0.5 >= x_lo && 0.5 <= x_hi) {
      const double x = fa.sx(0.5), y = fa.sy(*a);
      draw_line(img, x - 6, y - 6, x + 6, y + 6, kInk);
      draw_line(img, x - 6, y + 6, x + 6, y - 6, kInk);
    }
  }

  // The legend: families, the marks, the cells.
  int y = legend_y;
  for (std::size_t k = 0; k < families.size(); ++k) {
    const Rgb c = kColors[k % std::size(kColors)];
    draw_line(img, 90, y - 5, 124, y - 5, c);
    draw_disc(img, 107, y - 5, 3.5, c, true);
    draw_text(img, 134, y, 14,
              fmt::format("{} ({} members){}", families[k].surface, families[k].points.size(),
                          options.diffuse ? "; dotted, rings: the diffuse layer (Appendix B)"
                                          : ""),
              kInk);
    y += 24;
  }
  phase = 0.0;
  draw_line(img, 90, y - 5, 124, y - 5, kProfile, 6.0, 4.0, &phase);
  draw_text(img, 134, y, 14,
            "I_scp(min(alpha, 1 - alpha)): spheres, cylinders, planes (Section 2.3)", kInk);
  y += 24;
  draw_line(img, 101, y - 11, 113, y + 1, kInk);
  draw_line(img, 101, y + 1, 113, y - 11, kInk);
  draw_text(img, 134, y, 14, "minimal surfaces at alpha = 1/2: P 2.3451, D 3.8377, G 3.0915",
            kInk);
  y += 24;
  for (const Family& f : families)
    if (f.cell.is_object()) {
      draw_text(img, 90, y, 14, cell_text(f), kGreyInk);
      y += 24;
    }
  out.image = std::move(img);
  out.seconds = seconds_since(t0);
  return out;
}

std::string families_svg(const Image& image) {
  return fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" "
      "viewBox=\"0 0 {0} {1}\">\n<image width=\"{0}\" height=\"{1}\" "
      "href=\"data:image/png;base64,{2}\"/>\n</svg>\n",
      image.width, image.height, base64(encode_png(image)));
}

nlohmann::json write_families_figure(const std::filesystem::path& dir,
                                     const std::vector<nlohmann::json>& reports, bool diffuse) {
  const std::string name =
      (dir.filename().empty() ? dir.parent_path() : dir).filename().string();
  const FamiliesFigure figure = families_figure(
      reports, {.title = fmt::format("{}: families of CMC surfaces (Fig. 11)", name),
                .diffuse = diffuse});
  if (figure.image.rgb.empty()) return nullptr;
  write_png(dir / kFamiliesFigureName, figure.image);
  write_file_atomic(dir / kFamiliesSvgName, families_svg(figure.image));
  return {{"file", kFamiliesFigureName},
          {"seconds", figure.seconds},
          {"diffuse", diffuse},
          {"points", figure.points}};
}

nlohmann::json literature_json() {
  nlohmann::json areas = nlohmann::json::object();
  for (const MinimalSurfaceArea& a : minimal_surface_areas())
    areas[a.surface] = {{"area", a.area}, {"source", a.source}};
  nlohmann::json alpha = nlohmann::json::array(), area = nlohmann::json::array();
  for (int i = 1; i < 100; ++i) {
    alpha.push_back(i / 100.0);
    area.push_back(i_scp_of_fraction(i / 100.0));
  }
  return {{"minimal_surface_areas", areas},
          {"i_scp", {{"description", "I_scp(min(alpha, 1 - alpha)), Section 2.3"},
                     {"volume_fraction", alpha},
                     {"area", area}}}};
}

}  // namespace cmcsurf
