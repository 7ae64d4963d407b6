#include "measure/quality.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "measure/measures.h"
#include "../tests/test_fields.h"

namespace cmcsurf {
namespace {

// Ball of radius r about the cell centre with the tanh profile of width eps (phi > 1/2 inside).
Field ball(int n, double r, double eps) {
  Field f(n, 2);
  const double h = 1.0 / n;
  for_each_cell(n, [&](int i, int j, int k) {
    const double x = (i + 0.5) * h - 0.5, y = (j + 0.5) * h - 0.5, z = (k + 0.5) * h - 0.5;
    const double d = r - std::sqrt(x * x + y * y + z * z);
    f(i, j, k) = 0.5 * (1.0 + std::tanh(d / (2.0 * std::numbers::sqrt2 * eps)));
  });
  f.exchange_halo();
  return f;
}

TEST(Quality, IsoAreaOfTwoPlanesIsExact) {
  // phi depends on x only: every tetrahedron edge crossing x = x* is cut at x*, so the
  // piecewise-linear iso-surface is exactly the two planes, area 2 per unit cell.
  Field f(16, 1);
  for_each_cell(16, [&](int i, int j, int k) {
    f(i, j, k) = 0.5 + 0.45 * std::cos(2.0 * std::numbers::pi * (i + 0.3) / 16.0);
  });
  EXPECT_NEAR(iso_area(f), 2.0, 1e-12);
}

TEST(Quality, IsoAreaOfBallConvergesAtSecondOrder) {
  // Linear interpolation on tetrahedra: area error O(h^2); 1% at 32^3 (r = 8 h), 4x less at 64^3.
  const double r = 0.25, exact = 4.0 * std::numbers::pi * r * r;
  Field f32 = ball(32, r, 0.02), f64 = ball(64, r, 0.01);
  const double e32 = std::abs(iso_area(f32) - exact), e64 = std::abs(iso_area(f64) - exact);
  EXPECT_LT(e32 / exact, 0.01);
  EXPECT_LT(e64, 0.5 * e32);
}

TEST(Quality, LocalCurvatureOfBallIsNearlyConstant) {
  // Appendix B's kappa at cells of a ball of radius 8 h: H = 1/r up to the estimator's
  // discretization error (a few %) and a spread from the grid's anisotropy well below 1/r.
  Field f = ball(32, 0.25, 0.02);
  const CurvatureDistribution d = summarize(local_mean_curvature(f, kQualityBand));
  EXPECT_NEAR(d.mean, 4.0, 0.2);
  EXPECT_LT(d.std, 0.1 * 4.0);
  EXPECT_GT(d.cells, 100u);
}

TEST(Quality, FullBandMeanIsAppendixBMeanCurvature) {
  // With every cell in the band the weighted mean is Appendix B's surface average (round-off).
  Field f = testing::random_field(16, 2, 0.0, 1.0, 7);
  EXPECT_NEAR(summarize(local_mean_curvature(f, 1.0)).mean, mean_curvature(f), 1e-9);
  Field g = testing::gyroid_field(16, 2);
  EXPECT_NEAR(summarize(local_mean_curvature(g, 1.0)).mean, mean_curvature(g), 1e-9);
}

TEST(Quality, NodalPhaseFieldHasTheVolumeFractionAndGyroidArea) {
  const int n = 32;
  for (double alpha : {0.3, 0.5, 0.7}) {
    NodalPhaseField nodal = nodal_phase_field("G", alpha, n, 0.02);
    // Exact up to cells tied with the quantile (symmetric copies of one F value: the
    // gyroid's point group has order 48, and a few orbits may sit at the level).
    EXPECT_NEAR(volume_fraction(nodal.phi), alpha, 200.0 / (n * n * n)) << alpha;
  }
  // The level-0 nodal gyroid is within ~0.1% of the minimal gyroid (area 3.0919 per cubic
  // cell); the 32^3 iso-surface adds O(h^2) ~ 0.3%.
  NodalPhaseField g = nodal_phase_field("G", 0.5, n, 0.02);
  EXPECT_NEAR(g.level, 0.5, 1e-9);
  EXPECT_NEAR(iso_area(g.phi), 3.0919, 0.01 * 3.0919);
}

TEST(Quality, HistogramIsAFractionOfArea) {
  const std::vector<CurvatureSample> s = {{-1.0, 1.0}, {0.1, 2.0}, {0.2, 1.0}, {9.0, 4.0}};
  const std::vector<double> h = curvature_histogram(s, -0.5, 0.5, 4);
  ASSERT_EQ(h.size(), 4u);
  EXPECT_DOUBLE_EQ(h[0], 1.0 / 8.0);  // -1 clipped into the first bin
  EXPECT_DOUBLE_EQ(h[2], 3.0 / 8.0);
  EXPECT_DOUBLE_EQ(h[3], 4.0 / 8.0);  // 9 clipped into the last bin
  EXPECT_THROW(curvature_histogram(s, 1.0, 1.0, 4), std::invalid_argument);
}

}  // namespace
}  // namespace cmcsurf
