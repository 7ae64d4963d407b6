#include "mesh/morphometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "grid/field.h"

namespace cmcsurf {
namespace {

std::vector<std::uint8_t> cells(int n, const std::function<bool(double, double, double)>& in) {
  std::vector<std::uint8_t> v(std::size_t(n) * n * n);
  for_each_cell(n, [&](int i, int j, int k) {
    v[(std::size_t(k) * n + j) * n + i] = in((i + 0.5) / n, (j + 0.5) / n, (k + 0.5) / n);
  });
  return v;
}

// Two slabs 4 and 12 voxels thick (a quarter and three quarters of the phase's voxels): the
// 5th percentile reads the thin one, the median and the 95th the thick one, each within one
// voxel; the mean alone would read neither.
TEST(Morphometry, PercentilesSeparateTwoWalls) {
  const int n = 32;
  const auto two = cells(n, [](double, double, double z) {
    return std::abs(z - 0.25) < 2.0 / 32 || std::abs(z - 0.7) < 6.0 / 32;
  });
  const ThicknessStats s = thickness_stats(local_thickness(two, n), two, 1.0);
  EXPECT_NEAR(s.fraction, 16.0 / 32, 1e-12);
  EXPECT_NEAR(s.p5, 4.0, 1.0);
  EXPECT_NEAR(s.p50, 12.0, 1.0);
  EXPECT_NEAR(s.p95, 12.0, 1.0);
  EXPECT_NEAR(s.mean, 10.0, 1.0);
  EXPECT_LE(s.min, s.p5);
  EXPECT_LE(s.p95, s.max);
}

// The throat is the narrowest place a ball must pass: a channel along z of radius 8.5 voxels
// with a neck of radius 3.5 over 4 layers passes a ball of diameter 7 along z (2 r - 1, r the
// distance to the nearest voxel centre outside, at the neck between 3.5 and 4.5: 6 .. 8), and
// none along x or y (the channel does not wrap there). The gap between walls (a slab of pore
// 20 voxels thick, normal z) passes its whole width along x and y, nothing along z.
TEST(Morphometry, ThroatIsTheBottleneckOfTheDistanceMap) {
  const int n = 32;
  const double axis = 0.5 + 0.5 / n;
  const auto necked = cells(n, [&](double x, double y, double z) {
    const double r = std::abs(z - 0.5) < 2.0 / n ? 3.5 : 8.5;
    return std::hypot(x - axis, y - axis) < r / n;
  });
  const std::array<double, 3> t = throat_diameter(necked, n);
  EXPECT_EQ(t[0], 0.0);
  EXPECT_EQ(t[1], 0.0);
  EXPECT_NEAR(t[2], 7.0, 1.0);
  // Without the neck the same channel passes its own diameter, 17.
  const auto open = cells(n, [&](double x, double y, double) {
    return std::hypot(x - axis, y - axis) < 8.5 / n;
  });
  EXPECT_NEAR(throat_diameter(open, n)[2], 17.0, 1.0);
  const auto gap = cells(n, [](double, double, double z) { return std::abs(z - 0.5) < 10.0 / n; });
  const std::array<double, 3> g = throat_diameter(gap, n);
  EXPECT_NEAR(g[0], 20.0, 1.0);
  EXPECT_NEAR(g[1], 20.0, 1.0);
  EXPECT_EQ(g[2], 0.0);
}

}  // namespace
}  // namespace cmcsurf
