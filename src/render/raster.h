// A small software z-buffer rasterizer: triangles with per-vertex colour and normal, drawn into
// a supersampled canvas that keeps the nearest sample's interpolated colour and normal, shaded
// once per sample when resolved (Phong: ambient + two-sided Lambert + Blinn highlight) and
// box-filtered down to an Image. Offscreen by construction (no display, no GL).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "render/image.h"

namespace cmcsurf {

// A vertex in screen space: x right and y down in pixels of the canvas (pixel (i, j) covers
// [i, i+1) x [j, j+1)), z towards the viewer (a larger z hides a smaller one), n the unit
// normal in view space (z towards the viewer).
struct ScreenVertex {
  float x, y, z;
  Rgb color;
  float nx, ny, nz;
};

struct Shading {
  float ambient = 0.42f;
  float diffuse = 0.58f;
  float specular = 0.18f;
  float shininess = 40.0f;
  std::array<float, 3> light{-0.3f, -0.4f, 0.87f};  // towards the light, view space (y down)
};

class Canvas {
 public:
  // A canvas of width x height output pixels, drawn at `supersample`^2 samples per pixel.
  Canvas(int width, int height, int supersample, Rgb background);
  int width() const { return w_; }    // in samples
  int height() const { return h_; }
  int supersample() const { return ss_; }
  // Draws the triangles (vertex indices into v) with the depth test; coordinates in samples.
  void draw_triangles(std::span<const ScreenVertex> v,
                      std::span<const std::array<std::uint32_t, 3>> triangles);
  // Plain twin: every sample of the box of whole pixels around each triangle (and one more
  // row and column). draw_triangles tests fewer samples and writes the same bits.
  void draw_triangles_ref(std::span<const ScreenVertex> v,
                          std::span<const std::array<std::uint32_t, 3>> triangles);
  // Whether every sample's depth, colour and normal are the same bits as o's.
  bool same_samples(const Canvas& o) const;
  // A line of width ~1 output pixel in colour c, depth-tested against what is drawn (with a
  // small bias towards the viewer), coordinates in samples.
  void draw_line(float x0, float y0, float z0, float x1, float y1, float z1, Rgb c);
  // Samples covered by something drawn.
  std::size_t covered() const;
  // Shades every covered sample and box-filters down to width x height.
  Image resolve(const Shading& shading = {}) const;

 private:
  template <bool kTight>
  void draw(std::span<const ScreenVertex> v,
            std::span<const std::array<std::uint32_t, 3>> triangles);
  int w_, h_, ss_;
  Rgb background_;
  std::vector<Rgb> color_;                  // unshaded colour of the nearest sample
  std::vector<std::array<float, 3>> normal_;  // its normal; zero: unlit (lines)
  std::vector<float> depth_;                // -inf: empty
};

}  // namespace cmcsurf
