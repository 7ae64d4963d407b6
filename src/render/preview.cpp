#include "render/preview.h"

#include <stb_image_resize.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "parallel/first_exception.h"
#include "render/raster.h"
#include "render/text.h"

namespace cmcsurf {

namespace {

constexpr Rgb kInk{0.1f, 0.1f, 0.12f};
constexpr Rgb kGreyInk{0.38f, 0.38f, 0.4f};
constexpr Rgb kOutline{0.55f, 0.55f, 0.58f};
constexpr int kSupersample = 2;

// An orthographic view from azimuth 30 degrees, elevation 24 degrees, z up.
struct View {
  double right[3], up[3], toward[3];
  View() {
    const double az = 30.0 * M_PI / 180.0, el = 24.0 * M_PI / 180.0;
    toward[0] = std::cos(el) * std::cos(az);
    toward[1] = std::cos(el) * std::sin(az);
    toward[2] = std::sin(el);
    right[0] = -std::sin(az);
    right[1] = std::cos(az);
    right[2] = 0.0;
    up[0] = -std::sin(el) * std::cos(az);
    up[1] = -std::sin(el) * std::sin(az);
    up[2] = std::cos(el);
  }
  static double dot(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  }
};

}  // namespace

Image render_panel(const DrawSurface& s, int tiles, const ColorScale& scale, int size) {
  const View view;
  const double o = s.origin, extent = tiles;
  const double centre[3] = {o + 0.5 * extent, o + 0.5 * extent, o + 0.5 * extent};
  // Fit the box's outline into the panel with a margin.
  double reach = 0.0;
  for (int c = 0; c < 8; ++c) {
    const double p[3] = {(c & 1 ? 0.5 : -0.5) * extent, (c & 2 ? 0.5 : -0.5) * extent,
                         (c & 4 ? 0.5 : -0.5) * extent};
    reach = std::max({reach, std::abs(View::dot(p, view.right)), std::abs(View::dot(p, view.up))});
  }
  const double px = size * kSupersample;
  const double zoom = 0.47 * px / reach;
  auto project = [&](const double p[3], float out[3]) {
    const double q[3] = {p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]};
    out[0] = float(0.5 * px + zoom * View::dot(q, view.right));
    out[1] = float(0.5 * px - zoom * View::dot(q, view.up));
    out[2] = float(View::dot(q, view.toward));
  };
  Canvas canvas(size, size, kSupersample, {1, 1, 1});
  const std::size_t nv = s.positions.size();
  std::vector<ScreenVertex> v(nv);
  for (std::size_t i = 0; i < nv; ++i) {
    const auto& n = s.normals[i];
    const double nn[3] = {n[0], n[1], n[2]};
    v[i].nx = float(View::dot(nn, view.right));
    v[i].ny = float(-View::dot(nn, view.up));
    v[i].nz = float(View::dot(nn, view.toward));
    v[i].color = diverging(diverging_t(s.curvature[i], scale.centre, scale.half_range));
  }
  for (int tz = 0; tz < tiles; ++tz)
    for (int ty = 0; ty < tiles; ++ty)
      for (int tx = 0; tx < tiles; ++tx) {
        for (std::size_t i = 0; i < nv; ++i) {
          const auto& p = s.positions[i];
          const double q[3] = {p[0] + tx, p[1] + ty, p[2] + tz};
          float xyz[3];
          project(q, xyz);
          v[i].x = xyz[0];
          v[i].y = xyz[1];
          v[i].z = xyz[2];
        }
        canvas.draw_triangles(v, s.triangles);
      }
  // The box: its 12 edges, hidden parts hidden by the surface.
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c < 4; ++c) {
      double p0[3], p1[3];
      const int b = (a + 1) % 3, d = (a + 2) % 3;
      p0[a] = o;
      p1[a] = o + extent;
      p0[b] = p1[b] = o + (c & 1 ? extent : 0.0);
      p0[d] = p1[d] = o + (c & 2 ? extent : 0.0);
      float q0[3], q1[3];
      project(p0, q0);
      project(p1, q1);
      canvas.draw_line(q0[0], q0[1], q0[2], q1[0], q1[1], q1[2], kOutline);
    }
  return canvas.resolve();
}

namespace {

// A vertical colour bar with five ticks, its top-left corner at (x, y).
void draw_color_bar(Image& img, int x, int y, int width, int height, const ColorScale& scale,
                    const std::string& caption) {
  draw_text(img, x, y - 12, 16, caption, kInk);
  for (int j = 0; j < height; ++j) {
    const Rgb c = diverging(1.0 - (j + 0.5) / height);
    img.fill_rect(x, y + j, width, 1, c);
  }
  img.fill_rect(x - 1, y - 1, width + 2, 1, kGreyInk);
  img.fill_rect(x - 1, y + height, width + 2, 1, kGreyInk);
  img.fill_rect(x - 1, y - 1, 1, height + 2, kGreyInk);
  img.fill_rect(x + width, y - 1, 1, height + 2, kGreyInk);
  for (int k = 0; k <= 4; ++k) {
    const double t = 1.0 - k / 4.0;
    const double value = scale.centre + (2.0 * t - 1.0) * scale.half_range;
    const int ty = y + int(std::lround(k / 4.0 * (height - 1)));
    img.fill_rect(x + width, ty, 6, 1, kInk);
    draw_text(img, x + width + 9, ty + 5, 14, fmt::format("{:+.4g}", value), kInk);
  }
}

}  // namespace

Image render_preview(const DrawSurface& relaxed, const DrawSurface* nodal,
                     const ColorScale& scale, const PreviewLabels& labels) {
  const int cols = nodal ? 2 : 1;
  Image img(preview_width(nodal != nullptr), preview_height());
  draw_text(img, 16, 34, 26, labels.title, kInk);
  draw_text(img, 16, 60, 15, labels.subtitle, kGreyInk);
  const DrawSurface* surfaces[2] = {&relaxed, nodal};
  const std::string* headers[2] = {&labels.relaxed, &labels.nodal};
  // The panels are independent: one per thread, the 2 x 2 x 2 ones (8 times the triangles)
  // first, so that two threads finish together.
  Image panels[4];
  FirstException errors;
#pragma omp parallel for schedule(dynamic, 1)
  for (int q = 0; q < 2 * cols; ++q)
    errors.run([&] {
      const int k = q < cols ? 2 * q + 1 : 2 * (q - cols);  // panel 2 c + row
      panels[k] = render_panel(*surfaces[k / 2], k % 2 == 0 ? 1 : 2, scale, kPreviewPanel);
    });
  errors.rethrow();
  for (int c = 0; c < cols; ++c) {
    const int x = c * kPreviewPanel;
    draw_text(img, x + kPreviewPanel / 2, kPreviewTitle + 20, 17, *headers[c], kInk,
              Align::kCenter);
    for (int row = 0; row < 2; ++row)
      img.paste(panels[2 * c + row], x, kPreviewTitle + kPreviewHeader + row * kPreviewPanel);
    draw_text(img, x + 10, kPreviewTitle + kPreviewHeader + 20, 14, "unit cell", kGreyInk);
    draw_text(img, x + 10, kPreviewTitle + kPreviewHeader + kPreviewPanel + 20, 14, "2 × 2 × 2",
              kGreyInk);
  }
  if (nodal) img.fill_rect(kPreviewPanel, kPreviewTitle + 4, 1, img.height - kPreviewTitle - 8,
                           {0.85f, 0.85f, 0.85f});
  const int bar_top = kPreviewTitle + kPreviewHeader + 60;
  draw_color_bar(img, cols * kPreviewPanel + 16, bar_top, 26, img.height - bar_top - 60, scale,
                 "local H");
  return img;
}

Image resize_image(const Image& src, int width, int height) {
  Image out(width, height);
  if (!stbir_resize_uint8(src.rgb.data(), src.width, src.height, 0, out.rgb.data(), width, height,
                          0, 3))
    throw std::runtime_error("resize_image: stb_image_resize failed");
  return out;
}

Image render_gallery(const std::string& title, const std::vector<GalleryRow>& rows,
                     const ColorScale& scale, const Image& plot) {
  const int title_h = 48, label_w = 70, tile_label = 22, pad = 12, bar_w = 120;
  const int row_h = kGalleryTile + tile_label;
  std::size_t max_tiles = 1;
  for (const GalleryRow& r : rows) max_tiles = std::max(max_tiles, r.tiles.size());
  const int grid_h = std::max(int(rows.size()) * row_h, 1);
  // The plot at the height of the rows (at least 420 px, so that it stays readable).
  const int plot_h = plot.width > 0 ? std::max(grid_h, 420) : 0;
  const int plot_w =
      plot.width > 0 ? int(std::lround(double(plot.width) * plot_h / plot.height)) : 0;
  const int grid_x = plot_w + (plot_w ? pad : 0);
  const int width = grid_x + label_w + int(max_tiles) * kGalleryTile + bar_w;
  const int height = title_h + std::max(grid_h, plot_h) + pad;
  Image img(width, height);
  draw_text(img, 16, 32, 22, title, kInk);
  if (plot_w) img.paste(resize_image(plot, plot_w, plot_h), 0, title_h);
  std::vector<std::pair<std::size_t, std::size_t>> cells;  // (row, tile), drawn in parallel
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t t = 0; t < rows[r].tiles.size(); ++t) cells.emplace_back(r, t);
  std::vector<Image> tiles(cells.size());
  FirstException errors;
#pragma omp parallel for schedule(dynamic, 1)
  for (std::size_t k = 0; k < cells.size(); ++k)
    errors.run([&] {
      const GalleryTile& tile = rows[cells[k].first].tiles[cells[k].second];
      if (tile.surface) tiles[k] = render_panel(*tile.surface, 1, scale, kGalleryTile);
    });
  errors.rethrow();
  std::size_t next = 0;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const int y = title_h + int(r) * row_h;
    draw_text(img, grid_x + 8, y + kGalleryTile / 2 + 8, 22, rows[r].family, kInk);
    for (std::size_t t = 0; t < rows[r].tiles.size(); ++t) {
      const GalleryTile& tile = rows[r].tiles[t];
      const int x = grid_x + label_w + int(t) * kGalleryTile;
      if (tile.surface) img.paste(tiles[next], x, y);
      ++next;
      draw_text(img, x + kGalleryTile / 2, y + kGalleryTile + 14, 13, tile.label, kInk,
                Align::kCenter);
    }
  }
  const int bar_x = grid_x + label_w + int(max_tiles) * kGalleryTile + 16;
  draw_color_bar(img, bar_x, title_h + 30, 22, std::max(grid_h, plot_h) - 60, scale, "H");
  return img;
}

}  // namespace cmcsurf
