// The pictures of a run and of a sweep (docs/report.md): preview.png, the relaxed surface and
// its nodal twin, unit cell and 2x2x2 tiling, coloured by local mean curvature on one
// diverging scale, with a colour bar and a title; and a sweep's gallery.png, one row of unit
// cells per family beside the Fig. 11 plot.
#pragma once

#include <string>
#include <vector>

#include "render/draw_surface.h"
#include "render/image.h"

namespace cmcsurf {

// Colours: diverging(diverging_t(H, centre, half_range)).
struct ColorScale {
  double centre = 0.0;
  double half_range = 1.0;
};

// preview.png's layout, in pixels: a title band, a header over each column, two rows (unit
// cell, 2x2x2) of square panels per column (relaxed, then nodal if any), a colour bar.
inline constexpr int kPreviewPanel = 380;
inline constexpr int kPreviewTitle = 72;
inline constexpr int kPreviewHeader = 30;
inline constexpr int kPreviewColorBar = 130;
inline constexpr int preview_width(bool nodal) {
  return (nodal ? 2 : 1) * kPreviewPanel + kPreviewColorBar;
}
inline constexpr int preview_height() { return kPreviewTitle + kPreviewHeader + 2 * kPreviewPanel; }

// One panel: the surface over tiles^3 unit cells, seen along a fixed oblique direction
// (orthographic), lit, with the outline of the tiled box, size x size pixels.
Image render_panel(const DrawSurface& s, int tiles, const ColorScale& scale, int size);

struct PreviewLabels {
  std::string title;     // e.g. "G   α = 0.30   H = +0.9866"
  std::string subtitle;  // grid, epsilon, what the colours mean
  std::string relaxed;   // column headers
  std::string nodal;
};
Image render_preview(const DrawSurface& relaxed, const DrawSurface* nodal,
                     const ColorScale& scale, const PreviewLabels& labels);

struct GalleryTile {
  const DrawSurface* surface = nullptr;
  std::string label;  // under the tile
};
struct GalleryRow {
  std::string family;
  std::vector<GalleryTile> tiles;
};
inline constexpr int kGalleryTile = 150;
// Rows of unit cells on one colour scale (centre 0: the colour shows H itself, so a family's
// row runs from red to blue as alpha grows), beside `plot` (families.png, scaled to the rows'
// height; none if empty).
Image render_gallery(const std::string& title, const std::vector<GalleryRow>& rows,
                     const ColorScale& scale, const Image& plot);

// Box-filtered (or bilinear, when growing) resize by stb_image_resize.
Image resize_image(const Image& src, int width, int height);

}  // namespace cmcsurf
