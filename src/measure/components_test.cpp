#include "measure/components.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "../../tests/test_fields.h"
#include "measure/sharp_surface.h"
#include "measure/sharp_volume.h"
#include "measure/topology.h"
#include "measure/whole_surface.h"
#include "surfaces/nodal_level.h"

namespace cmcsurf {
namespace {

using testing::kPi;
using testing::sample_at_centres;
using testing::tanh_profile;

// Balls of radii 0.15 (label 0: met first, lower z) and 0.2, as in SharpSurface's test of
// local curvature.
Field two_balls(int n) {
  return sample_at_centres(n, 2, [](double x, double y, double z) {
    const double d1 = 0.15 - std::hypot(x - 0.25, y - 0.25, z - 0.25);
    const double d2 = 0.2 - std::hypot(x - 0.7, y - 0.7, z - 0.7);
    return tanh_profile(std::max(d1, d2), 0.01);
  });
}

TEST(Components, LabelsAndRegionsOfTwoBalls) {
  const Field phi = two_balls(32);
  const ComponentLabels l = label_components(phi, 1);
  EXPECT_EQ(l.count, 2);
  const ComponentLabels outside = label_components(phi, 2);
  EXPECT_EQ(outside.count, 1);
  // Every cell has a region; a cell of a component lies in its own region; the ball centres
  // are where they should be.
  for (std::size_t q = 0; q < l.region.size(); ++q) {
    ASSERT_GE(l.region[q], 0);
    if (l.component[q] >= 0) {
      EXPECT_EQ(l.region[q], l.component[q]);
    }
  }
  const auto at = [](double x) { return int(x * 32); };
  EXPECT_EQ(l.component[std::size_t((at(0.25) * 32 + at(0.25)) * 32 + at(0.25))], 0);
  EXPECT_EQ(l.component[std::size_t((at(0.7) * 32 + at(0.7)) * 32 + at(0.7))], 1);
  // The corner cell (0, 0, 0) is nearer the small ball through the periodic wrap than the
  // large one: 0.23 / h steps against 0.28 / h.
  EXPECT_EQ(l.region[0], 0);
}

// Each ball's boundary measured alone: area 4 pi r^2 and H = 1/r to the second-order
// estimators' 64^3 accuracy for 10-13 cells of radius (3e-3, measure/sharp_surface_test), chi
// 2 exactly, the volume to 1e-3; and the pieces add up to the whole surface's area (the same
// triangles: the regions' borders lie in the bulk).
TEST(Components, InterfacesOfTwoBalls) {
  const Field phi = two_balls(64);
  const std::vector<InterfaceMeasures> m = interface_measures(phi);
  ASSERT_EQ(m.size(), 2u);
  const double r[2] = {0.15, 0.2};
  double area = 0.0;
  for (int c = 0; c < 2; ++c) {
    EXPECT_EQ(m[c].phase, 1);
    EXPECT_EQ(m[c].component, c);
    EXPECT_NEAR(m[c].area / (4 * kPi * r[c] * r[c]), 1.0, 3e-3) << c;
    EXPECT_NEAR(m[c].mean_curvature * r[c], 1.0, 3e-3) << c;
    EXPECT_LT(m[c].mean_curvature_std * r[c], 2e-2) << c;
    EXPECT_EQ(m[c].euler_characteristic, 2) << c;
    EXPECT_NEAR(m[c].gaussian_curvature_integral / (4 * kPi), 1.0, 2e-2) << c;
    EXPECT_NEAR(m[c].enclosed_volume / (4.0 / 3.0 * kPi * std::pow(r[c], 3)), 1.0, 1e-3) << c;
    area += m[c].area;
  }
  EXPECT_NEAR(area, sharp_measures(phi).area, 1e-12);
}

// The components' volumes partition the sharp volume fraction (each dual cell counted once):
// they add up to it to round-off, also where two networks come within a few cells of each
// other (the double gyroid's seed at 32^3).
TEST(Components, VolumesAddUpToTheWhole) {
  const Field balls = two_balls(32);
  const NodalLevelSet g = double_level_set("G", 0.35, 32);
  const Field networks = nodal_tanh_profile(g, 0.02);
  for (const Field* phi : {&balls, &networks}) {
    const ComponentLabels l = label_components(*phi, 1);
    ASSERT_EQ(l.count, 2);
    const std::vector<double> v = component_volumes(*phi, l);
    EXPECT_NEAR(v[0] + v[1], sharp_volume_fraction(*phi), 1e-14);
    EXPECT_GT(v[0], 0.0);
    EXPECT_GT(v[1], 0.0);
  }
}

// The complement: two ball-shaped holes in phase 1 are listed as phase 2's components, with
// their H negative (phase 1 concave around them).
TEST(Components, HolesAreListedByPhase2) {
  Field phi = two_balls(32);
  for (int k = 0; k < 32; ++k)
    for (int j = 0; j < 32; ++j)
      for (int i = 0; i < 32; ++i) phi(i, j, k) = 1.0 - phi(i, j, k);
  phi.exchange_halo();
  const std::vector<InterfaceMeasures> m = interface_measures(phi);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0].phase, 2);
  EXPECT_LT(m[0].mean_curvature, 0.0);
  EXPECT_NEAR(m[1].enclosed_volume / (4.0 / 3.0 * kPi * 0.008), 1.0, 1e-2);
}

// One gyroid: one piece, the whole surface (chi -8 per cell).
TEST(Components, SingleGyroidIsOnePiece) {
  const NodalLevelSet g = nodal_level_set("G", 0.5, 32);
  const Field phi = nodal_tanh_profile(g, 0.02);
  const std::vector<InterfaceMeasures> m = interface_measures(phi);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].euler_characteristic, -8);
  EXPECT_NEAR(m[0].area, sharp_measures(phi).area, 1e-12);
  EXPECT_NEAR(m[0].enclosed_volume, sharp_volume_fraction(phi), 1e-12);
}

// The double gyroid's seed {|F| > c}: two networks in one matrix, each a gyroid labyrinth
// (chi -8 for its boundary), mirror images under the inversion x -> -x (F is odd), which maps
// cell centres to cell centres and the Kuhn split to itself: equal to round-off.
TEST(Components, DoubleGyroidSeedHasTwoNetworks) {
  const NodalLevelSet g = double_level_set("G", 0.35, 32);
  EXPECT_NEAR(g.volume_fraction, 0.35, 1e-6);
  const Field phi = nodal_tanh_profile(g, 0.02);
  const std::vector<InterfaceMeasures> m = interface_measures(phi);
  ASSERT_EQ(m.size(), 2u);
  for (const InterfaceMeasures& x : m) {
    EXPECT_EQ(x.phase, 1);
    EXPECT_EQ(x.euler_characteristic, -8);
  }
  EXPECT_NEAR(m[0].enclosed_volume, m[1].enclosed_volume, 1e-12);
  EXPECT_NEAR(m[0].area, m[1].area, 1e-12);
  EXPECT_NEAR(m[0].mean_curvature, m[1].mean_curvature, 1e-9);
}

// What the final measures hand over, computed here by the functions they use.
WholeSurfaceMeasures whole_of(const Field& phi) {
  WholeSurfaceMeasures w;
  w.counts = phase_components(phi);
  w.surface = sharp_measures(phi);
  w.euler_phase1 = euler_characteristic(phi);
  w.euler_phase2 = euler_characteristic_phase2(phi);
  w.volume_fraction = sharp_volume_fraction(phi);
  return w;
}

// The shortcut for one component gives what labelling gives: the same surface sums bit for bit
// (component_field is phi itself), the enclosed volume the same fractions summed in another
// order (N^3 terms in [0, 1] over N^3: 1e-13 is a thousand times their round-off). Several
// components (balls, the double gyroid's networks) take the labelling path, unchanged.
TEST(Components, WholeSurfaceShortcutMatchesLabelling) {
  const NodalLevelSet g = nodal_level_set("G", 0.5, 32);
  const Field gyroid = nodal_tanh_profile(g, 0.02);
  const NodalLevelSet dg = double_level_set("G", 0.35, 32);
  const Field networks = nodal_tanh_profile(dg, 0.02);
  const Field balls = two_balls(32);
  Field holes = two_balls(32);
  for (int k = 0; k < holes.n(); ++k)
    for (int j = 0; j < holes.n(); ++j)
      for (int i = 0; i < holes.n(); ++i) holes(i, j, k) = 1.0 - holes(i, j, k);
  holes.exchange_halo();
  for (const Field* phi : {&gyroid, &networks, &balls, static_cast<const Field*>(&holes)}) {
    const std::vector<InterfaceMeasures> a = interface_measures(*phi, whole_of(*phi));
    const std::vector<InterfaceMeasures> b = interface_measures(*phi);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t c = 0; c < a.size(); ++c) {
      EXPECT_EQ(a[c].phase, b[c].phase);
      EXPECT_EQ(a[c].component, b[c].component);
      EXPECT_EQ(a[c].area, b[c].area);
      EXPECT_EQ(a[c].mean_curvature, b[c].mean_curvature);
      EXPECT_EQ(a[c].mean_curvature_std, b[c].mean_curvature_std);
      EXPECT_EQ(a[c].gaussian_curvature_integral, b[c].gaussian_curvature_integral);
      EXPECT_EQ(a[c].euler_characteristic, b[c].euler_characteristic);
      EXPECT_NEAR(a[c].enclosed_volume, b[c].enclosed_volume, 1e-13);
    }
  }
  EXPECT_EQ(interface_measures(gyroid, whole_of(gyroid)).size(), 1u);
  EXPECT_EQ(interface_measures(holes, whole_of(holes))[0].phase, 2);
}

}  // namespace
}  // namespace cmcsurf
