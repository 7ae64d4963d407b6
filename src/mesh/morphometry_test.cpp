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

// A box, not periodic: the periodic cell's slab and channel measured again with the box's
// faces cutting them. A wall cut by the box keeps its thickness up to the cut (balls stay
// inside, beyond the box is outside the wall); a pore that meets a face goes on past it.
std::vector<std::uint8_t> box_cells(const std::array<int, 3>& d,
                                    const std::function<bool(int, int, int)>& in) {
  std::vector<std::uint8_t> v(std::size_t(d[0]) * d[1] * d[2]);
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i) v[(std::size_t(k) * d[1] + j) * d[0] + i] = in(i, j, k);
  return v;
}

TEST(Morphometry, BoxWallKeepsItsThicknessToTheCut) {
  const std::array<int, 3> d{24, 20, 16};
  // A slab 5 voxels thick (normal x), cut by the box on its four other sides.
  const auto slab = box_cells(d, [](int i, int, int) { return i >= 8 && i < 13; });
  const ThicknessStats s = thickness_stats(box_local_thickness(slab, d, true), slab, 1.0);
  EXPECT_EQ(s.p5, 5.0);
  EXPECT_EQ(s.max, 5.0);
  // Where two cuts meet (an edge of the box) no ball of 5 reaches the corner voxels.
  EXPECT_GE(s.min, 3.0);
  // The same slab on the box's face: the face cuts it, beyond is outside, still 5.
  const auto face = box_cells(d, [](int i, int, int) { return i < 5; });
  EXPECT_EQ(thickness_stats(box_local_thickness(face, d, true), face, 1.0).max, 5.0);
  // As a pore (beyond the box is no wall), the gap at the face is as wide as the balls that
  // reach past it: more than its 5 voxels inside the box.
  EXPECT_GT(thickness_stats(box_local_thickness(face, d, false), face, 1.0).min, 5.0);
  // The transform itself: exact squared distances to the nearest outside voxel.
  const std::vector<double> d2 = box_edt2(slab, d, true);
  const std::size_t mid = (std::size_t(8) * d[1] + 10) * d[0];  // j = 10, k = 8
  EXPECT_EQ(d2[mid + 8], 1.0);
  EXPECT_EQ(d2[mid + 10], 9.0);  // 3 to either side; the box's faces are farther
  EXPECT_EQ(d2[mid + 7], 0.0);
  EXPECT_EQ(d2[10], 1.0);  // j = 0, k = 0: one voxel from the box's face, beyond it outside
}

// The channel of ThroatIsTheBottleneckOfTheDistanceMap in a box: along z a ball of its neck's
// diameter (7, within a voxel) passes from face to face; along x and y nothing does.
TEST(Morphometry, BoxThroatIsTheNeckBetweenFaces) {
  const std::array<int, 3> d{32, 32, 32};
  const double axis = 16.5;  // on a voxel centre, as in the periodic test
  const auto necked = box_cells(d, [&](int i, int j, int k) {
    const double r = std::abs(k + 0.5 - 16.0) < 2.0 ? 3.5 : 8.5;
    return std::hypot(i + 0.5 - axis, j + 0.5 - axis) < r;
  });
  const std::array<double, 3> t = box_throat_diameter(necked, d);
  EXPECT_EQ(t[0], 0.0);
  EXPECT_EQ(t[1], 0.0);
  EXPECT_NEAR(t[2], 7.0, 1.0);
  // The periodic cell's throat of the same voxels: the same bottleneck.
  EXPECT_EQ(t[2], throat_diameter(necked, 32)[2]);
}

}  // namespace
}  // namespace cmcsurf
