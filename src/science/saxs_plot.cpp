#include "science/saxs_plot.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "render/text.h"

namespace cmcsurf {

namespace {

constexpr Rgb kInk{0.1f, 0.1f, 0.12f};
constexpr Rgb kGrey{0.6f, 0.6f, 0.62f};
constexpr Rgb kLine{0.14f, 0.35f, 0.75f};
constexpr Rgb kMark{0.8f, 0.25f, 0.2f};

// An anti-aliased line of width ~1.5 px: samples every half pixel, each blended as a disc.
void draw_line(Image& img, double x0, double y0, double x1, double y1, Rgb c) {
  const int steps = std::max(1, int(2 * std::hypot(x1 - x0, y1 - y0)));
  for (int s = 0; s <= steps; ++s) {
    const double x = x0 + (x1 - x0) * s / steps, y = y0 + (y1 - y0) * s / steps;
    for (int py = int(std::floor(y - 1)); py <= int(std::ceil(y + 1)); ++py)
      for (int px = int(std::floor(x - 1)); px <= int(std::ceil(x + 1)); ++px) {
        const double d = std::hypot(px + 0.5 - x, py + 0.5 - y);
        if (d < 1.0) img.blend(px, py, c, float(0.6 * (1.0 - d)));
      }
  }
}

// A "nice" tick step for a span: 1, 2 or 5 times a power of ten, about 6 ticks.
double nice_step(double span) {
  const double raw = span / 6, p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0})
    if (m * p >= raw) return m * p;
  return 10 * p;
}

}  // namespace

Image draw_saxs_plot(const PowderPattern& pattern, const std::string& title, int width,
                     int height) {
  Image img(width, height);
  const int left = 80, right = width - 24, top = 48, bottom = height - 90;
  const double q_max = pattern.q.empty() ? 1.0 : pattern.q.back();
  double i_max = 0;
  for (double v : pattern.intensity) i_max = std::max(i_max, v);
  if (!(i_max > 0)) i_max = 1;
  const double decades = 6, y_hi = std::log10(i_max) + 0.2, y_lo = y_hi - decades;
  auto px = [&](double q) { return left + (right - left) * q / q_max; };
  auto py = [&](double v) {
    const double y = std::clamp(std::log10(std::max(v, 1e-300)), y_lo, y_hi);
    return bottom - (bottom - top) * (y - y_lo) / (y_hi - y_lo);
  };
  // Present reflections: a faint line and a sqrt(s) label when there is room.
  int last_label = -1000;
  for (std::size_t j = 0; j < pattern.peak_q.size(); ++j) {
    const int x = int(std::lround(px(pattern.peak_q[j])));
    img.fill_rect(x, top, 1, bottom - top, {0.93f, 0.86f, 0.85f});
    img.fill_rect(x, bottom, 1, 8, kMark);
    const std::string label = fmt::format("√{}", pattern.peak_s[j]);
    const int w = text_width(label, 13);
    if (x - w / 2 > last_label + 4) {
      draw_text(img, x, bottom + 22, 13, label, kMark, Align::kCenter);
      last_label = x + w / 2;
    }
  }
  // Axes and ticks.
  img.fill_rect(left, top, 1, bottom - top + 1, kInk);
  img.fill_rect(left, bottom, right - left + 1, 1, kInk);
  const double step = nice_step(q_max);
  for (double q = 0; q <= q_max * (1 + 1e-9); q += step) {
    const int x = int(std::lround(px(q)));
    img.fill_rect(x, bottom + 8, 1, 5, kInk);
    draw_text(img, x, bottom + 42, 13, fmt::format("{:g}", q), kInk, Align::kCenter);
  }
  for (int e = int(std::ceil(y_lo)); e <= int(std::floor(y_hi)); ++e) {
    const int y = int(std::lround(py(std::pow(10.0, e))));
    img.fill_rect(left - 5, y, 5, 1, kInk);
    img.fill_rect(left + 1, y, right - left, 1, {0.92f, 0.92f, 0.93f});
    draw_text(img, left - 8, y + 5, 13, fmt::format("1e{}", e), kInk, Align::kRight);
  }
  // The pattern.
  for (std::size_t i = 1; i < pattern.q.size(); ++i)
    draw_line(img, px(pattern.q[i - 1]), py(pattern.intensity[i - 1]), px(pattern.q[i]),
              py(pattern.intensity[i]), kLine);
  draw_text(img, (left + right) / 2, height - 18, 15, "q (1/nm); marks: allowed √s", kInk,
            Align::kCenter);
  draw_text(img, 12, top - 14, 15, "I(q)", kInk);
  draw_text(img, (left + right) / 2, 28, 16, title, kInk, Align::kCenter);
  img.fill_rect(left, top, right - left, 1, kGrey);
  return img;
}

}  // namespace cmcsurf
