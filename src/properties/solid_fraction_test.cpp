// Voxel solid fractions from a phase field and the gyroid test cells.
#include "properties/solid_fraction.h"

#include <gtest/gtest.h>

#include <cmath>

#include "measure/sharp_volume.h"
#include "../tests/test_fields.h"

namespace cmcsurf::properties {
namespace {

double mean(const std::vector<double>& s) {
  double m = 0.0;
  for (double v : s) m += v / double(s.size());
  return m;
}

// Same interpolant as linear_volume_fraction: the means agree to round-off.
TEST(SolidFraction, FromPhiMatchesTheLinearVolumeFraction) {
  const Field phi = testing::gyroid_field(16, 1);
  const auto s = solid_fraction_from_phi(phi);
  EXPECT_NEAR(mean(s), linear_volume_fraction(phi), 1e-13);
  for (double v : s) {
    EXPECT_GE(v, 0.0);
    EXPECT_LE(v, 1.0);
  }
}

// phi linear in x with its 1/2 level at x = 0.3: dual cells (between centres i and i + 1) are
// solid where x > 0.3, and the cut one is filled in proportion.
TEST(SolidFraction, FromPhiIsExactForAPlane) {
  const int n = 10;
  const Field phi = testing::sample_at_centres(n, 1, [](double x, double, double) {
    return 0.5 + 2.0 * (x - 0.32);  // not periodic: check the dual cells away from the wrap
  });
  const auto s = solid_fraction_from_phi(phi);
  for (int i = 0; i + 1 < n; ++i) {
    const double x0 = (i + 0.5) / n, x1 = (i + 1.5) / n;
    const double exact = std::clamp((x1 - 0.32) / (x1 - x0), 0.0, 1.0);
    EXPECT_NEAR(s[(std::size_t(3) * n + 4) * n + i], exact, 1e-12) << i;
  }
}

TEST(SolidFraction, GyroidCellsHaveTheirPorosity) {
  for (auto kind : {GyroidSolid::network, GyroidSolid::sheet}) {
    const auto s = nodal_gyroid_solid_fraction(16, kind, 0.7);
    EXPECT_NEAR(mean(s), 0.3, 1e-9);
    EXPECT_NEAR(mean(restrict_solid_fraction(16, s)), 0.3, 1e-9);
  }
}

}  // namespace
}  // namespace cmcsurf::properties
