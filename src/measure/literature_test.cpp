#include "measure/literature.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace cmcsurf {
namespace {

constexpr double pi = std::numbers::pi;

// Each branch is the area of its shape of volume v in the unit cell, from its radius.
TEST(Literature, IscpBranchesAreTheShapesAreas) {
  const double v_sphere = 0.1;  // r = (3 v / 4 pi)^(1/3), A = 4 pi r^2
  const double r = std::cbrt(3.0 * v_sphere / (4.0 * pi));
  EXPECT_NEAR(i_scp(v_sphere), 4.0 * pi * r * r, 1e-14);
  const double v_cyl = 0.25;  // a cylinder of unit length: v = pi r^2, A = 2 pi r
  EXPECT_NEAR(i_scp(v_cyl), 2.0 * pi * std::sqrt(v_cyl / pi), 1e-14);
  EXPECT_EQ(i_scp(0.4), 2.0);  // two planes
}

// The branches meet where they change: the sphere of radius 1/3 and the cylinder of the same
// volume have area 4 pi / 9; the cylinder of radius 1/2 and the plane pair have area 2.
TEST(Literature, IscpIsContinuous) {
  const double v1 = 4.0 * pi / 81.0, v2 = 1.0 / pi;
  EXPECT_NEAR(i_scp(v1), 4.0 * pi / 9.0, 1e-14);
  EXPECT_NEAR(i_scp(std::nextafter(v1, 1.0)), 4.0 * pi / 9.0, 1e-12);
  EXPECT_NEAR(i_scp(v2), 2.0, 1e-14);
  EXPECT_EQ(i_scp(std::nextafter(v2, 1.0)), 2.0);
  EXPECT_EQ(i_scp_of_fraction(0.7), i_scp(1.0 - 0.7));  // the smaller phase
}

// The documented constants (docs/families.md), G at Schoen's 3.0915, not 3.0919.
TEST(Literature, MinimalSurfaceAreasAreTheDocumentedOnes) {
  EXPECT_EQ(minimal_surface_areas().size(), 3u);
  EXPECT_EQ(minimal_surface_area("P"), 2.3451);
  EXPECT_EQ(minimal_surface_area("D"), 3.8377);
  EXPECT_EQ(minimal_surface_area("G"), 3.0915);
  EXPECT_FALSE(minimal_surface_area("I-WP").has_value());
}

}  // namespace
}  // namespace cmcsurf
