#include "measure/topology.h"

#include <gtest/gtest.h>

#include <cmath>

#include "../../tests/test_fields.h"
#include "surfaces/initial.h"

namespace cmcsurf {
namespace {

using testing::sample_at_centres;

Field nodal(const char* surface, int n) {
  InitialFieldParams p;
  p.surface = surface;
  return make_initial_field(p, n, 2);  // F + 1/2: phase 1 = {F > 0}
}

TEST(Topology, BallSlabTorusAndTheirComplements) {
  const int n = 32;
  const Field ball = sample_at_centres(n, 2, [](double x, double y, double z) {
    return std::hypot(x - 0.5, y - 0.5, z - 0.5) < 0.3 ? 1.0 : 0.0;
  });
  const Field slab = sample_at_centres(n, 2, [](double x, double, double) {
    return x > 0.3 && x < 0.6 ? 1.0 : 0.0;
  });
  const Field ring = sample_at_centres(n, 2, [](double x, double y, double z) {
    const double r = std::hypot(x - 0.5, y - 0.5) - 0.3;  // solid torus around the z axis
    return std::hypot(r, z - 0.5) < 0.1 ? 1.0 : 0.0;
  });
  EXPECT_EQ(euler_characteristic(ball), 1);
  EXPECT_EQ(euler_characteristic(slab), 0);   // T^2 x I
  EXPECT_EQ(euler_characteristic(ring), 0);
  // The complement of a ball in the 3-torus: chi(T^3) - chi(ball) + chi(sphere) = 0 - 1 + 2.
  const Field outside = sample_at_centres(n, 2, [](double x, double y, double z) {
    return std::hypot(x - 0.5, y - 0.5, z - 0.5) < 0.3 ? 0.0 : 1.0;
  });
  EXPECT_EQ(euler_characteristic(outside), 1);
  // Two balls: two components.
  const Field two = sample_at_centres(n, 2, [](double x, double y, double z) {
    return std::hypot(x - 0.25, y - 0.5, z - 0.5) < 0.15 ||
                   std::hypot(x - 0.75, y - 0.5, z - 0.5) < 0.15
               ? 1.0
               : 0.0;
  });
  EXPECT_EQ(euler_characteristic(two), 2);
}

// The nodal surfaces at alpha = 1/2 (level F = 0): both phases connected, surfaces of genus
// 3 (P), 5 (G) and 9 (D) per cubic cell, so chi = 1 - g.
TEST(Topology, NodalSurfacesHaveTheirGenus) {
  EXPECT_EQ(euler_characteristic(nodal("P", 32)), -2);
  EXPECT_EQ(euler_characteristic(nodal("G", 32)), -4);
  EXPECT_EQ(euler_characteristic(nodal("D", 32)), -8);
}

TEST(Topology, MatchesReferenceOnRandomField) {
  const Field f = testing::random_field(24, 1, 0.0, 1.0, 7);
  for (double level : {0.2, 0.5, 0.8})
    EXPECT_EQ(euler_characteristic(f, level), euler_characteristic_ref(f, level)) << level;
}

}  // namespace
}  // namespace cmcsurf
