#include "render/raster.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace cmcsurf {

namespace {

constexpr float kEmpty = -std::numeric_limits<float>::infinity();

Rgb shade(const Rgb& c, float nx, float ny, float nz, const Shading& s) {
  const float len = std::sqrt(nx * nx + ny * ny + nz * nz);
  if (len > 0.0f) {
    nx /= len;
    ny /= len;
    nz /= len;
  }
  if (nz < 0.0f) {  // two-sided: light the side that faces the viewer
    nx = -nx;
    ny = -ny;
    nz = -nz;
  }
  const auto& l = s.light;
  const float ll = std::sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
  const float lx = l[0] / ll, ly = l[1] / ll, lz = l[2] / ll;
  const float lambert = std::max(0.0f, nx * lx + ny * ly + nz * lz);
  // Blinn: half vector between the light and the view direction (0, 0, 1).
  float hx = lx, hy = ly, hz = lz + 1.0f;
  const float hl = std::sqrt(hx * hx + hy * hy + hz * hz);
  hx /= hl;
  hy /= hl;
  hz /= hl;
  const float nh = nx * hx + ny * hy + nz * hz;
  const float spec = nh > 0.5f ? s.specular * std::pow(nh, s.shininess) : 0.0f;
  const float k = s.ambient + s.diffuse * lambert;
  return {c.r * k + spec, c.g * k + spec, c.b * k + spec};
}

}  // namespace

Canvas::Canvas(int width, int height, int supersample, Rgb background)
    : w_(width * supersample),
      h_(height * supersample),
      ss_(supersample),
      background_(background),
      color_(std::size_t(w_) * h_, background),
      normal_(std::size_t(w_) * h_, {0.0f, 0.0f, 0.0f}),
      depth_(std::size_t(w_) * h_, kEmpty) {}

namespace {

// Triangles at least this well shaped (twice the area over the longest edge squared, about the
// sine of the smallest angle) get the tight box of sample centres; slivers keep the whole-pixel
// box, where a float edge test could accept a centre outside their exact extent.
constexpr float kWellShaped = 0.05f;
// How far outside a well-shaped triangle's extent (in samples) a centre is still tested: for a
// centre that far out some edge line is >= kMargin * kWellShaped / 2 ~ 6e-3 samples away,
// twenty times what float rounding of the edge functions moves a line at coordinates < 4096.
constexpr float kMargin = 0.25f;

}  // namespace

// The rasterizer of both: tight (well-shaped triangles get the tight box) or the reference's
// box. The sample loop is the reference's text, so that the compiler forms the same
// operations (with -march=native it fuses some multiply-adds; an equivalent rewrite of the
// loop, the tests in one branch, changed three bytes of the README's preview.png).
template <bool kTight>
void Canvas::draw(std::span<const ScreenVertex> v,
                  std::span<const std::array<std::uint32_t, 3>> triangles) {
  for (const auto& t : triangles) {
    const ScreenVertex& a = v[t[0]];
    const ScreenVertex& b = v[t[1]];
    const ScreenVertex& c = v[t[2]];
    // Twice the signed area; either winding is drawn.
    const float area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (area == 0.0f || !std::isfinite(area)) continue;
    const float xmin = std::min({a.x, b.x, c.x}), xmax = std::max({a.x, b.x, c.x});
    const float ymin = std::min({a.y, b.y, c.y}), ymax = std::max({a.y, b.y, c.y});
    // The reference's box: every sample of the pixels the extent touches, and one more.
    int x0 = std::max(0, int(std::floor(xmin)));
    int x1 = std::min(w_ - 1, int(std::ceil(xmax)));
    int y0 = std::max(0, int(std::floor(ymin)));
    int y1 = std::min(h_ - 1, int(std::ceil(ymax)));
    if constexpr (kTight) {
      const auto sq = [](float dx, float dy) { return dx * dx + dy * dy; };
      const float longest = std::max(
          {sq(b.x - a.x, b.y - a.y), sq(c.x - b.x, c.y - b.y), sq(a.x - c.x, a.y - c.y)});
      if (std::abs(area) >= kWellShaped * longest) {
        // Only the centres x + 1/2 within kMargin of [xmin, xmax] (about half the box for a
        // triangle a few samples wide).
        x0 = std::max(x0, int(std::ceil(xmin - 0.5f - kMargin)));
        x1 = std::min(x1, int(std::floor(xmax - 0.5f + kMargin)));
        y0 = std::max(y0, int(std::ceil(ymin - 0.5f - kMargin)));
        y1 = std::min(y1, int(std::floor(ymax - 0.5f + kMargin)));
      }
    }
    const float inv = 1.0f / area;
    for (int y = y0; y <= y1; ++y) {
      const float py = y + 0.5f;
      for (int x = x0; x <= x1; ++x) {
        const float px = x + 0.5f;
        // Barycentric weights from the edge functions (sample at the pixel centre).
        const float wa = ((b.x - px) * (c.y - py) - (b.y - py) * (c.x - px)) * inv;
        const float wb = ((c.x - px) * (a.y - py) - (c.y - py) * (a.x - px)) * inv;
        const float wc = 1.0f - wa - wb;
        if (wa < 0.0f || wb < 0.0f || wc < 0.0f) continue;
        const float z = wa * a.z + wb * b.z + wc * c.z;
        const std::size_t i = std::size_t(y) * w_ + x;
        if (!(z > depth_[i])) continue;
        depth_[i] = z;
        color_[i] = {wa * a.color.r + wb * b.color.r + wc * c.color.r,
                     wa * a.color.g + wb * b.color.g + wc * c.color.g,
                     wa * a.color.b + wb * b.color.b + wc * c.color.b};
        normal_[i] = {wa * a.nx + wb * b.nx + wc * c.nx, wa * a.ny + wb * b.ny + wc * c.ny,
                      wa * a.nz + wb * b.nz + wc * c.nz};
      }
    }
  }
}

void Canvas::draw_triangles(std::span<const ScreenVertex> v,
                            std::span<const std::array<std::uint32_t, 3>> triangles) {
  draw<true>(v, triangles);
}

void Canvas::draw_triangles_ref(std::span<const ScreenVertex> v,
                                std::span<const std::array<std::uint32_t, 3>> triangles) {
  draw<false>(v, triangles);
}

bool Canvas::same_samples(const Canvas& o) const {
  const auto bits = [](const auto& a, const auto& b) {
    return a.size() == b.size() &&
           std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0;
  };
  return w_ == o.w_ && h_ == o.h_ && bits(depth_, o.depth_) && bits(color_, o.color_) &&
         bits(normal_, o.normal_);
}

void Canvas::draw_line(float x0, float y0, float z0, float x1, float y1, float z1, Rgb c) {
  const float len = std::max(std::abs(x1 - x0), std::abs(y1 - y0));
  const int steps = std::max(1, int(std::ceil(len)));
  const int half = ss_ / 2;
  const float bias = 1e-3f;
  for (int s = 0; s <= steps; ++s) {
    const float f = float(s) / steps;
    const int x = int(x0 + f * (x1 - x0)), y = int(y0 + f * (y1 - y0));
    const float z = z0 + f * (z1 - z0) + bias;
    for (int dy = -half; dy < ss_ - half; ++dy)
      for (int dx = -half; dx < ss_ - half; ++dx) {
        const int px = x + dx, py = y + dy;
        if (px < 0 || py < 0 || px >= w_ || py >= h_) continue;
        const std::size_t i = std::size_t(py) * w_ + px;
        if (z < depth_[i]) continue;
        color_[i] = c;
        normal_[i] = {0.0f, 0.0f, 0.0f};
      }
  }
}

std::size_t Canvas::covered() const {
  return std::size_t(
      std::count_if(depth_.begin(), depth_.end(), [](float d) { return d != kEmpty; }));
}

Image Canvas::resolve(const Shading& shading) const {
  Image out(w_ / ss_, h_ / ss_);
  const float norm = 1.0f / float(ss_ * ss_);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      float r = 0, g = 0, b = 0;
      for (int j = 0; j < ss_; ++j)
        for (int i = 0; i < ss_; ++i) {
          const std::size_t k = std::size_t(y * ss_ + j) * w_ + (x * ss_ + i);
          const auto& n = normal_[k];
          const bool lit = depth_[k] != kEmpty && (n[0] != 0.0f || n[1] != 0.0f || n[2] != 0.0f);
          const Rgb c = lit ? shade(color_[k], n[0], n[1], n[2], shading) : color_[k];
          r += c.r;
          g += c.g;
          b += c.b;
        }
      std::uint8_t* p = out.pixel(x, y);
      p[0] = to_byte(r * norm);
      p[1] = to_byte(g * norm);
      p[2] = to_byte(b * norm);
    }
  return out;
}

}  // namespace cmcsurf
