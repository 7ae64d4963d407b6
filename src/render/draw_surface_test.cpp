#include "render/draw_surface.h"

#include <gtest/gtest.h>

#include <cmath>

#include "measure/sharp_surface.h"
#include "surfaces/initial.h"

namespace cmcsurf {
namespace {

TEST(DrawSurface, StrideIsTheLeastDivisorWithinTheLimit) {
  EXPECT_EQ(draw_stride(256, 64), 4);
  EXPECT_EQ(draw_stride(64, 64), 1);
  EXPECT_EQ(draw_stride(96, 64), 2);
  EXPECT_EQ(draw_stride(96, 48), 2);
  EXPECT_EQ(draw_stride(128, 48), 4);
  EXPECT_EQ(draw_stride(24, 64), 1);
}

// A tanh ball of radius r: vertices lie on the sphere, H = 1/r at every vertex (phase 1 inside
// is convex: H > 0), normals point out of the ball, and the cell is [h/2, 1 + h/2]^3.
TEST(DrawSurface, BallHasItsRadiusCurvatureAndOutwardNormals) {
  const int n = 32;
  const double r = 0.3, eps = 0.02;
  InitialFieldParams init;
  init.surface = "sphere";
  init.radius = r;
  init.epsilon = eps;
  const Field phi = make_initial_field(init, n, 2);
  Field psi(n, 2);
  tanh_profile_inverse(phi, psi);
  for (int max_cells : {32, 16}) {
    const DrawSurface s = draw_surface(psi, max_cells);
    EXPECT_EQ(s.lattice_cells, max_cells);
    EXPECT_FLOAT_EQ(s.origin, 0.5f / n);
    ASSERT_GT(s.triangles.size(), 500u);
    double worst_r = 0.0, worst_h = 0.0, least_dot = 1.0;
    for (std::size_t v = 0; v < s.positions.size(); ++v) {
      double d[3], len = 0.0;
      for (int a = 0; a < 3; ++a) {
        d[a] = s.positions[v][a] - 0.5;
        len += d[a] * d[a];
        EXPECT_GE(s.positions[v][a], s.origin);
        EXPECT_LE(s.positions[v][a], s.origin + 1.0f);
      }
      len = std::sqrt(len);
      worst_r = std::max(worst_r, std::abs(len - r));
      worst_h = std::max(worst_h, std::abs(s.curvature[v] * r - 1.0));
      least_dot = std::min(least_dot, (d[0] * s.normals[v][0] + d[1] * s.normals[v][1] +
                                       d[2] * s.normals[v][2]) / len);
    }
    // Linear interpolation over a lattice of spacing H = 1/max_cells misses the sphere by at
    // most (sqrt3 H)^2 / (8 r) (a cube diagonal's sagitta): 1.2e-3 at 32, 4.9e-3 at 16 cells;
    // H from the 32^3 psi is good to O(h^2) (~1 %).
    const double cell = 1.0 / max_cells;
    EXPECT_LT(worst_r, 3.0 * cell * cell / (8.0 * r) + 2e-4) << max_cells;
    EXPECT_LT(worst_h, 0.02) << max_cells;
    EXPECT_GT(least_dot, 0.99) << max_cells;
  }
}

TEST(DrawSurface, SpreadIsAnAreaQuantileOfTheDeviation) {
  DrawSurface s;
  // Two unit right triangles (area 1/2 each) with H 1 and 3: deviations from 2 are both 1.
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  s.normals.assign(6, {0, 0, 1});
  s.curvature = {1, 1, 1, 3, 3, 3};
  s.triangles = {{0, 1, 2}, {3, 4, 5}};
  EXPECT_DOUBLE_EQ(curvature_spread(s, 2.0, 0.95), 1.0);
  EXPECT_DOUBLE_EQ(curvature_spread(s, 1.0, 0.4), 0.0);
  EXPECT_DOUBLE_EQ(curvature_spread(s, 1.0, 0.95), 2.0);
}

}  // namespace
}  // namespace cmcsurf
