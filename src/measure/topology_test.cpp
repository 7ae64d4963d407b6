#include "measure/topology.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <numbers>

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
  for (double level : {0.2, 0.5, 0.8}) {
    EXPECT_EQ(euler_characteristic(f, level), euler_characteristic_ref(f, level)) << level;
    EXPECT_EQ(euler_characteristic_phase2(f, level), euler_characteristic_phase2_ref(f, level))
        << level;
  }
}

// Both labyrinths of P, G, D at alpha = 1/2 are congruent handlebodies: the same chi, one
// component each, one surface of chi = 2 chi(phase 1) (P -4, G -8, D -16).
TEST(Topology, BothPhasesOfTheNodalSurfaces) {
  for (const char* s : {"P", "G", "D"}) {
    const Field f = nodal(s, 32);
    EXPECT_EQ(euler_characteristic_phase2(f), euler_characteristic(f)) << s;
    const PhaseComponents c = phase_components(f);
    EXPECT_EQ(c.phase1, 1) << s;
    EXPECT_EQ(c.phase2, 1) << s;
    EXPECT_EQ(c.interfaces, 1) << s;
  }
}

TEST(Topology, ComponentsOfBallsSlabsAndTwoNetworks) {
  const int n = 32;
  // Two balls in a matrix: two phase-1 components, one matrix, two spheres.
  const Field two = sample_at_centres(n, 2, [](double x, double y, double z) {
    return std::hypot(x - 0.25, y - 0.5, z - 0.5) < 0.15 ||
                   std::hypot(x - 0.75, y - 0.5, z - 0.5) < 0.15
               ? 1.0
               : 0.0;
  });
  PhaseComponents c = phase_components(two);
  EXPECT_EQ(c.phase1, 2);
  EXPECT_EQ(c.phase2, 1);
  EXPECT_EQ(c.interfaces, 2);
  EXPECT_EQ(euler_characteristic_phase2(two), 2);  // T^3 minus two balls: chi 0 - 2 + 2 x 2
  // A ball crossing the periodic faces is one component.
  const Field corner = sample_at_centres(n, 2, [](double x, double y, double z) {
    const double dx = std::min(x, 1 - x), dy = std::min(y, 1 - y), dz = std::min(z, 1 - z);
    return std::hypot(dx, dy, dz) < 0.2 ? 1.0 : 0.0;
  });
  c = phase_components(corner);
  EXPECT_EQ(c.phase1, 1);
  EXPECT_EQ(c.phase2, 1);
  // A slab: one component of each phase; its two planes count as one interface.
  const Field slab = sample_at_centres(n, 2, [](double x, double, double) {
    return x > 0.3 && x < 0.6 ? 1.0 : 0.0;
  });
  c = phase_components(slab);
  EXPECT_EQ(c.phase1, 1);
  EXPECT_EQ(c.phase2, 1);
  EXPECT_EQ(c.interfaces, 1);
  // Two gyroid networks in a matrix, {|F| > 0.9}: two phase-1 components of chi -4 each.
  const Field dg = sample_at_centres(n, 2, [](double x, double y, double z) {
    const double w = 2 * std::numbers::pi;
    const double f = std::sin(w * x) * std::cos(w * y) + std::sin(w * y) * std::cos(w * z) +
                     std::sin(w * z) * std::cos(w * x);
    return std::abs(f) > 0.9 ? 1.0 : 0.0;
  });
  c = phase_components(dg);
  EXPECT_EQ(c.phase1, 2);
  EXPECT_EQ(c.phase2, 1);
  EXPECT_EQ(c.interfaces, 2);
  EXPECT_EQ(euler_characteristic(dg), -8);
  EXPECT_EQ(euler_characteristic_phase2(dg), -8);
}

// The slab-parallel union-find against the serial one: random fields (hundreds of components of
// one phase at the levels beyond 26-connected percolation, about 0.1 and 0.9), nodal fields, at
// thread counts that split the 36 planes evenly, unevenly and into slabs of 1 to 6 planes.
TEST(Topology, PhaseComponentsMatchReference) {
  const int saved = omp_get_max_threads();
  const Field noise = testing::random_field(36, 1, 0.0, 1.0, 11);
  const Field g = nodal("G", 36), p = nodal("P", 32);
  for (int threads : {1, 2, 5, 7}) {
    omp_set_num_threads(threads);
    for (double level : {0.05, 0.3, 0.5, 0.7, 0.95}) {
      for (const Field* f : {&noise, &g, &p}) {
        const PhaseComponents a = phase_components(*f, level);
        const PhaseComponents b = phase_components_ref(*f, level);
        EXPECT_EQ(a.phase1, b.phase1) << threads << " " << level;
        EXPECT_EQ(a.phase2, b.phase2) << threads << " " << level;
        EXPECT_EQ(a.interfaces, b.interfaces) << threads << " " << level;
      }
    }
  }
  omp_set_num_threads(saved);
  // Not a check that cannot fail: the noise has many components of one phase at either end.
  const PhaseComponents c = phase_components(noise, 0.95), d = phase_components(noise, 0.05);
  EXPECT_GT(c.phase1, 100);
  EXPECT_GT(c.interfaces, 100);
  EXPECT_GT(d.phase2, 100);
}
}  // namespace
}  // namespace cmcsurf
