#include "surfaces/nodal_level.h"

#include <gtest/gtest.h>

#include <cmath>

#include "measure/measures.h"
#include "measure/sharp_surface.h"
#include "measure/sharp_volume.h"

namespace cmcsurf {
namespace {

TEST(NodalLevel, HitsTheSharpVolumeFraction) {
  for (double alpha : {0.25, 0.5, 0.7}) {
    const NodalLevelSet g = nodal_level_set("G", alpha, 32);
    EXPECT_NEAR(g.volume_fraction, alpha, 1e-7) << alpha;
    Field shifted = nodal_level_function(g);  // zero on the surface: volume of {psi + 1/2 > 1/2}
    for_each_cell(shifted, [&](int i, int j, int k) { shifted(i, j, k) += 0.5; });
    shifted.exchange_halo();
    EXPECT_NEAR(sharp_volume_fraction(shifted), alpha, 1e-7) << alpha;
  }
  // The gyroid is balanced: its level 0 (F + 1/2 = 1/2) splits the cell in halves.
  EXPECT_NEAR(nodal_level_set("G", 0.5, 32).level, 0.5, 1e-6);
}

TEST(NodalLevel, NodalGyroidAreaIsNearTheMinimalGyroid) {
  // The level-0 nodal gyroid is within ~0.1% of the minimal gyroid (area 3.0919 per cubic
  // cell); the sharp estimator at 32^3 adds O(h^2).
  const NodalLevelSet g = nodal_level_set("G", 0.5, 32);
  const LevelSetSurface s = level_set_surface(nodal_level_function(g));
  EXPECT_NEAR(s.area, 3.0919, 0.003 * 3.0919);
  EXPECT_NEAR(s.mean_curvature, 0.0, 1e-6);  // balanced: H averages to zero
  EXPECT_GT(s.mean_curvature_std, 0.05);     // but the nodal gyroid is not minimal
}

TEST(NodalLevel, TanhProfileHasTheSameSurface) {
  const NodalLevelSet p = nodal_level_set("P", 0.3, 32);
  const Field phi = nodal_tanh_profile(p, 0.02);
  const SharpMeasures m = sharp_measures(phi);
  const LevelSetSurface s = level_set_surface(nodal_level_function(p));
  EXPECT_NEAR(m.area, s.area, 2e-3 * s.area);
  EXPECT_NEAR(sharp_volume_fraction(phi), 0.3, 2e-3);
}

TEST(NodalLevel, RefusesNonNodalSurfacesAndBadFractions) {
  EXPECT_THROW(nodal_level_set("sphere", 0.5, 16), std::invalid_argument);
  EXPECT_THROW(nodal_level_set("G", 1.0, 16), std::invalid_argument);
}

}  // namespace
}  // namespace cmcsurf
