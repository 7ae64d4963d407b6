#include "mesh/channel_radius.h"

#include <gtest/gtest.h>

#include <cmath>

#include "surfaces/initial.h"
#include "test_fields.h"

namespace cmcsurf {
namespace {

using testing::sample_at_centres;

// A ball of phase 1: every cell of it lies in the ball itself, so each radius is R up to the
// voxels: the largest ball of cells is centred up to sqrt(3) h / 2 off the ball's centre
// (measured 0.274 for 0.3 at 32^3: within 1.5 h).
TEST(ChannelRadius, BallHasItsRadiusEverywhere) {
  const int n = 32;
  const double r0 = 0.3, h = 1.0 / n;
  const Field psi = sample_at_centres(n, 1, [&](double x, double y, double z) {
    return r0 - std::hypot(x - 0.5, y - 0.5, z - 0.5);
  });
  const ChannelRadius r = channel_radius(psi);
  EXPECT_NEAR(r.phase1.max, r0, 1.5 * h);
  EXPECT_NEAR(r.phase1.p50, r0, 1.5 * h);
  EXPECT_NEAR(r.phase1.p5, r0, 1.5 * h);
  EXPECT_NEAR(r.phase1.fraction, 4.0 / 3.0 * M_PI * r0 * r0 * r0, 3e-3);
  // Outside the ball the largest ball sits in the corners of the cell: sqrt(3)/2 - r0 from the
  // ball (at the cell's corner) and at most the gap to the next periodic image, 1/2 - ... .
  EXPECT_GT(r.phase2.max, 0.5 - r0 - h);
  EXPECT_LT(r.phase2.max, std::sqrt(3.0) / 2.0 - r0 + h);
}

// A cylinder along z: the same radius for every cell of it.
TEST(ChannelRadius, CylinderHasItsRadiusEverywhere) {
  const int n = 32;
  const double r0 = 0.2, h = 1.0 / n;
  const Field psi = sample_at_centres(n, 1, [&](double x, double y, double) {
    return r0 - std::hypot(x - 0.5, y - 0.5);
  });
  const ChannelRadius r = channel_radius(psi);
  EXPECT_NEAR(r.phase1.max, r0, 1.5 * h);  // measured 0.182 at 32^3
  EXPECT_NEAR(r.phase1.mean, r0, 1.5 * h);
  EXPECT_NEAR(r.phase1.p5, r0, 1.5 * h);
}

// P at alpha = 1/2: a shift by half the cell maps one labyrinth onto the other, and on an even
// grid cell centres onto cell centres, so the two labyrinths' radii agree exactly.
TEST(ChannelRadius, PrimitiveLabyrinthsAtHalfAreEqual) {
  const int n = 32;
  const Field psi = sample_at_centres(
      n, 1, [](double x, double y, double z) { return nodal_value("P", x, y, z) - 0.5; });
  const ChannelRadius r = channel_radius(psi);
  EXPECT_DOUBLE_EQ(r.phase1.max, r.phase2.max);
  EXPECT_DOUBLE_EQ(r.phase1.p50, r.phase2.p50);
  EXPECT_NEAR(r.phase1.mean, r.phase2.mean, 1e-12);  // sums in another order
  // The widest point is the node, whose ball touches the surface first along the body
  // diagonals (3 cos X = 0: at sqrt(3) / 4 = 0.433; along a face diagonal sqrt(2) / 3 = 0.471,
  // never along an axis): the largest inscribed sphere, less the voxels' bias.
  EXPECT_GT(r.phase1.max, 0.433 - 1.5 / n);
  EXPECT_LT(r.phase1.max, 0.433);
  EXPECT_LT(r.phase1.p5, r.phase1.p50);
}

}  // namespace
}  // namespace cmcsurf
