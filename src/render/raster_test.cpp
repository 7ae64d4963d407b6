#include "render/raster.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "render/colormap.h"
#include "render/text.h"

namespace cmcsurf {
namespace {

// Flat colour: no lighting, so a pixel shows exactly the interpolated colour.
constexpr Shading kFlat{1.0f, 0.0f, 0.0f, 1.0f, {0.0f, 0.0f, 1.0f}};

ScreenVertex vertex(float x, float y, float z, Rgb c) { return {x, y, z, c, 0, 0, 1}; }

// A UV sphere of radius r (pixels) centred at (cx, cy): `slices` around, `stacks` pole to pole.
void sphere(float cx, float cy, float r, int slices, int stacks, std::vector<ScreenVertex>& v,
            std::vector<std::array<std::uint32_t, 3>>& t) {
  for (int i = 0; i <= stacks; ++i) {
    const double theta = M_PI * i / stacks;
    for (int j = 0; j < slices; ++j) {
      const double phi = 2 * M_PI * j / slices;
      const float x = float(std::sin(theta) * std::cos(phi)), y = float(std::cos(theta)),
                  z = float(std::sin(theta) * std::sin(phi));
      v.push_back({cx + r * x, cy + r * y, r * z, {1, 0, 0}, x, y, z});
    }
  }
  for (int i = 0; i < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      const std::uint32_t a = i * slices + j, b = i * slices + (j + 1) % slices;
      t.push_back({a, b, a + slices});
      t.push_back({b, b + slices, a + slices});
    }
}

TEST(Raster, SphereCoversItsDiscArea) {
  const int w = 200, ss = 2;
  const float r = 70.0f * ss;
  std::vector<ScreenVertex> v;
  std::vector<std::array<std::uint32_t, 3>> t;
  sphere(100.0f * ss, 100.0f * ss, r, 128, 64, v, t);
  Canvas canvas(w, w, ss, {1, 1, 1});
  canvas.draw_triangles(v, t);
  // A 128-gon silhouette has (128 / 2 pi) sin(2 pi / 128) = 0.9996 of the disc's area; the
  // sample count along the rim adds O(1 / r) ~ 0.5 %.
  const double disc = M_PI * r * r / (double(w * ss) * (w * ss));
  const double covered = double(canvas.covered()) / (double(w * ss) * (w * ss));
  EXPECT_NEAR(covered / disc, 1.0, 5e-3);
  // Nothing outside the bounding square of the disc.
  const Image img = canvas.resolve(kFlat);
  for (int x = 0; x < w; ++x) {
    EXPECT_EQ(img.pixel(x, 0)[0], 255);
    EXPECT_EQ(img.pixel(x, 0)[1], 255);
  }
  // The centre is the sphere's colour.
  EXPECT_EQ(img.pixel(100, 100)[0], 255);
  EXPECT_EQ(img.pixel(100, 100)[1], 0);
}

TEST(Raster, NearerTriangleWinsInEitherDrawingOrder) {
  const Rgb red{1, 0, 0}, blue{0, 0, 1};
  const std::vector<std::array<std::uint32_t, 3>> one = {{0, 1, 2}};
  for (int order = 0; order < 2; ++order) {
    Canvas canvas(40, 40, 1, {1, 1, 1});
    const std::vector<ScreenVertex> near = {vertex(0, 0, 1, red), vertex(40, 0, 1, red),
                                            vertex(0, 40, 1, red)};
    const std::vector<ScreenVertex> far = {vertex(0, 0, -1, blue), vertex(40, 40, -1, blue),
                                           vertex(0, 40, -1, blue)};
    if (order == 0) {
      canvas.draw_triangles(near, one);
      canvas.draw_triangles(far, one);
    } else {
      canvas.draw_triangles(far, one);
      canvas.draw_triangles(near, one);
    }
    const Image img = canvas.resolve(kFlat);
    EXPECT_EQ(img.pixel(5, 30)[0], 255) << "order " << order;  // both cover it: red wins
    EXPECT_EQ(img.pixel(5, 30)[2], 0) << "order " << order;
    EXPECT_EQ(img.pixel(30, 38)[2], 255) << "order " << order;  // blue alone
    EXPECT_EQ(img.pixel(38, 5)[1], 255) << "order " << order;   // neither: background
  }
}

TEST(Raster, ColourIsInterpolatedAcrossATriangle) {
  Canvas canvas(100, 100, 1, {1, 1, 1});
  const std::vector<ScreenVertex> v = {vertex(0, 0, 0, {0, 0, 0}), vertex(100, 0, 0, {1, 1, 1}),
                                       vertex(0, 100, 0, {0, 0, 0})};
  canvas.draw_triangles(v, std::vector<std::array<std::uint32_t, 3>>{{0, 1, 2}});
  const Image img = canvas.resolve(kFlat);
  // At pixel centre x = 20.5 (y small) the weight of the white vertex is 0.205.
  EXPECT_NEAR(img.pixel(20, 2)[0], 0.205 * 255, 1.0);
}

TEST(Raster, TightBoxDrawsTheSameSamplesAsTheReference) {
  // Triangles a few samples wide (the preview's), large ones, slivers and near-degenerate
  // ones, some reaching off the canvas, their corners often on or next to sample centres,
  // where the edge tests are closest to the box's edge; drawn in one order by both.
  std::mt19937 rng(29);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const auto snap = [&](float x) {  // half of them on a 1/8 lattice (centres are on it)
    return unit(rng) < 0.5f ? std::round(x * 8.0f) / 8.0f : x;
  };
  std::vector<ScreenVertex> v;
  std::vector<std::array<std::uint32_t, 3>> t;
  for (std::uint32_t k = 0; k < 20000; ++k) {
    const int kind = int(k % 4);
    const float size = kind == 0 ? 40.0f : kind == 3 ? 0.7f : 4.0f;
    const float cx = -5.0f + 110.0f * unit(rng), cy = -5.0f + 110.0f * unit(rng);
    float x[3], y[3];
    for (int c = 0; c < 3; ++c) {
      x[c] = snap(cx + size * (unit(rng) - 0.5f));
      y[c] = snap(cy + size * (unit(rng) - 0.5f));
    }
    if (kind == 2) {  // a sliver: the third corner near the line through the first two
      const float f = unit(rng), d = 1e-3f * (unit(rng) - 0.5f);
      x[2] = x[0] + f * (x[1] - x[0]) + d;
      y[2] = y[0] + f * (y[1] - y[0]) - d;
    }
    for (int c = 0; c < 3; ++c)
      v.push_back({x[c], y[c], unit(rng), {unit(rng), unit(rng), unit(rng)}, unit(rng),
                   unit(rng), unit(rng)});
    t.push_back({3 * k, 3 * k + 1, 3 * k + 2});
  }
  Canvas fast(100, 100, 1, {1, 1, 1}), ref(100, 100, 1, {1, 1, 1});
  fast.draw_triangles(v, t);
  ref.draw_triangles_ref(v, t);
  EXPECT_GT(ref.covered(), 9000u);
  EXPECT_TRUE(fast.same_samples(ref));
}

TEST(Raster, LightingIsTwoSidedAndDarkensGrazingNormals) {
  Shading s;
  s.specular = 0.0f;
  s.light = {0.0f, 0.0f, 1.0f};
  Canvas canvas(30, 10, 1, {1, 1, 1});
  std::vector<ScreenVertex> v;
  const float nz[3] = {1.0f, -1.0f, 0.2f};  // facing, facing away (flipped), grazing
  for (int k = 0; k < 3; ++k) {
    const float x = 10.0f * k;
    for (const auto& [px, py] : {std::pair{x, 0.0f}, {x + 10, 0.0f}, {x, 10.0f}, {x + 10, 10.0f}})
      v.push_back({px, py, 0, {1, 1, 1}, 0, std::sqrt(1 - nz[k] * nz[k]), nz[k]});
  }
  std::vector<std::array<std::uint32_t, 3>> t;
  for (std::uint32_t k = 0; k < 3; ++k) {
    t.push_back({4 * k, 4 * k + 1, 4 * k + 2});
    t.push_back({4 * k + 1, 4 * k + 3, 4 * k + 2});
  }
  canvas.draw_triangles(v, t);
  const Image img = canvas.resolve(s);
  EXPECT_EQ(img.pixel(5, 5)[0], 255);    // ambient + diffuse = 1
  EXPECT_EQ(img.pixel(15, 5)[0], 255);   // the back side is lit like the front
  EXPECT_NEAR(img.pixel(25, 5)[0], (s.ambient + s.diffuse * 0.2f) * 255, 1.0);
}

TEST(Colormap, EndpointsCentreAndClamping) {
  const auto stops = diverging_stops();
  const Rgb lo = diverging(0.0), mid = diverging(0.5), hi = diverging(1.0);
  EXPECT_FLOAT_EQ(lo.r, stops.front().color.r);
  EXPECT_FLOAT_EQ(lo.b, stops.front().color.b);
  EXPECT_FLOAT_EQ(hi.r, stops.back().color.r);
  EXPECT_GT(lo.b, lo.r);  // blue below the centre
  EXPECT_GT(hi.r, hi.b);  // red above
  EXPECT_NEAR(mid.r, mid.b, 0.01f);  // grey at the centre
  EXPECT_FLOAT_EQ(diverging(-3.0).r, lo.r);
  EXPECT_FLOAT_EQ(diverging(7.0).r, hi.r);
  EXPECT_FLOAT_EQ(diverging(std::nan("")).r, lo.r);
  EXPECT_DOUBLE_EQ(diverging_t(1.3, 1.3, 0.2), 0.5);
  EXPECT_NEAR(diverging_t(1.5, 1.3, 0.2), 1.0, 1e-15);
  EXPECT_NEAR(diverging_t(1.1, 1.3, 0.2), 0.0, 1e-15);
  // Cool below the centre, warm above it.
  for (int k = 0; k <= 64; ++k) {
    const Rgb c = diverging(k / 64.0);
    // Braces: EXPECT_* expand to an if/else, which a bare if would make ambiguous.
    if (k < 31) {
      EXPECT_LT(c.r, c.b) << k;
    }
    if (k > 33) {
      EXPECT_GT(c.r, c.b) << k;
    }
  }
}

TEST(Text, DrawsInkWithinItsWidth) {
  Image img(200, 40);
  const int w = text_width("H = +1.25 α", 20);
  EXPECT_GT(w, text_width("H = +1.2", 20));
  EXPECT_LT(w, 200);
  draw_text(img, 10, 28, 20, "H = +1.25 α", {0, 0, 0});
  int ink = 0, outside = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const bool dark = img.pixel(x, y)[0] < 128;
      ink += dark;
      outside += dark && (x < 10 || x > 10 + w + 1);
    }
  EXPECT_GT(ink, 60);
  EXPECT_EQ(outside, 0);
}

}  // namespace
}  // namespace cmcsurf
