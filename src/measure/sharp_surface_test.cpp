#include "measure/sharp_surface.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "../tests/test_fields.h"

namespace cmcsurf {
namespace {

using testing::kPi;

template <class F>
Field sample(int n, F f) {
  return testing::sample_at_centres(n, 2, f);
}

using testing::tanh_profile;

// A ball of phase 1 of radius r, centred off the grid's symmetry points.
Field tanh_ball(int n, double r, double epsilon) {
  return sample(n, [=](double x, double y, double z) {
    const double dx = x - 0.5 - 0.013, dy = y - 0.5 + 0.021, dz = z - 0.5 - 0.007;
    return tanh_profile(r - std::sqrt(dx * dx + dy * dy + dz * dz), epsilon);
  });
}

TEST(SharpSurface, BallAreaAndCurvatureConvergeAtSecondOrderAtFixedEpsilon) {
  const double r = 0.3, eps = 0.01;
  double area_err[3], h_err[3];
  const int grids[3] = {32, 64, 128};
  for (int g = 0; g < 3; ++g) {
    const SharpMeasures m = sharp_measures(tanh_ball(grids[g], r, eps));
    area_err[g] = std::abs(m.area / (4 * kPi * r * r) - 1.0);
    h_err[g] = std::abs(m.mean_curvature * r - 1.0);
    // A ball has constant H: the spread is estimator error only, and it shrinks with h.
    EXPECT_LT(m.mean_curvature_std * r, 8.0 * h_err[g] + 2e-3) << grids[g];
    // The Richardson estimate is within a factor of 3 of the true error.
    EXPECT_LT(m.area_error, 3.0 * std::abs(m.area - 4 * kPi * r * r) + 1e-6) << grids[g];
    EXPECT_GT(m.area_error, std::abs(m.area - 4 * kPi * r * r) / 3.0) << grids[g];
  }
  for (int g = 1; g < 3; ++g) {
    EXPECT_GT(std::log2(area_err[g - 1] / area_err[g]), 1.7) << grids[g];
    EXPECT_GT(std::log2(h_err[g - 1] / h_err[g]), 1.7) << grids[g];
  }
  EXPECT_LT(area_err[2], 2e-4);
  EXPECT_LT(h_err[2], 2e-4);
}

TEST(SharpSurface, TiltedPlanesAreFlatWithTheirExactArea) {
  // Two parallel planes of normal (1, 2, 0)/sqrt5, periodic: a slab of phase 1 of width 1/2
  // along the normal within the period cell of the lattice; area 2 sqrt5 per unit cell.
  const Field phi = sample(48, [](double x, double y, double) {
    const double s = std::sin(2 * kPi * (x + 2 * y));
    return tanh_profile(std::asin(std::clamp(s, -1.0, 1.0)) / (2 * kPi * std::sqrt(5.0)), 0.01);
  });
  const SharpMeasures m = sharp_measures(phi);
  EXPECT_NEAR(m.area, 2 * std::sqrt(5.0), 2e-3);
  EXPECT_NEAR(m.mean_curvature, 0.0, 1e-9);
  EXPECT_LT(m.mean_curvature_std, 0.05);
}

TEST(SharpSurface, CylinderHasHalfItsCurvature) {
  const double r = 0.25;
  const Field phi = sample(64, [=](double x, double y, double) {
    return tanh_profile(r - std::hypot(x - 0.5, y - 0.5), 0.01);
  });
  const SharpMeasures m = sharp_measures(phi);
  EXPECT_NEAR(m.area, 2 * kPi * r, 2e-3 * 2 * kPi * r);
  EXPECT_NEAR(m.mean_curvature, 0.5 / r, 2e-3 / r);
}

TEST(SharpSurface, CurvatureIsLocal) {
  // Two balls of radii 0.15 and 0.25 far apart: the samples split into two groups around 1/r.
  const Field phi = sample(64, [](double x, double y, double z) {
    const double d1 = 0.15 - std::sqrt((x - 0.25) * (x - 0.25) + (y - 0.25) * (y - 0.25) +
                                       (z - 0.25) * (z - 0.25));
    const double d2 = 0.2 - std::sqrt((x - 0.7) * (x - 0.7) + (y - 0.7) * (y - 0.7) +
                                      (z - 0.7) * (z - 0.7));
    return tanh_profile(std::max(d1, d2), 0.01);
  });
  std::vector<CurvatureSample> samples;
  sharp_measures(phi, &samples);
  double a_small = 0.0, a_large = 0.0;
  for (const CurvatureSample& s : samples) {
    if (std::abs(s.h - 1 / 0.15) < 0.05 / 0.15) a_small += s.w;
    if (std::abs(s.h - 1 / 0.2) < 0.05 / 0.2) a_large += s.w;
  }
  EXPECT_NEAR(a_small, 4 * kPi * 0.15 * 0.15, 0.01);
  EXPECT_NEAR(a_large, 4 * kPi * 0.2 * 0.2, 0.01);
}

TEST(SharpSurface, ReferenceTwinGivesTheSameSamples) {
  // A gyroid-like level set with noise, on a grid large enough for the parallel path.
  const int n = kParallelMinN + 8;
  Field psi = sample(n, [](double x, double y, double z) {
    const double w = 2 * kPi;
    return std::sin(w * x) * std::cos(w * y) + std::sin(w * y) * std::cos(w * z) +
           std::sin(w * z) * std::cos(w * x) + 0.3 + 0.01 * std::sin(97.0 * x * y + 31.0 * z);
  });
  std::vector<CurvatureSample> fast, ref;
  const LevelSetSurface a = level_set_surface(psi, &fast);
  const LevelSetSurface b = level_set_surface_ref(psi, &ref);
  ASSERT_EQ(fast.size(), ref.size());
  ASSERT_GT(fast.size(), 1000u);
  for (std::size_t t = 0; t < fast.size(); ++t) {
    ASSERT_NEAR(fast[t].h, ref[t].h, 1e-9 * (1 + std::abs(ref[t].h))) << t;
    ASSERT_NEAR(fast[t].w, ref[t].w, 1e-15) << t;
    // K is a ratio of fourth powers of differences: 1e-9 relative to the K^2 ~ H^2 scale.
    ASSERT_NEAR(fast[t].k, ref[t].k, 1e-9 * (1 + ref[t].h * ref[t].h)) << t;
  }
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_NEAR(a.area, b.area, 1e-12 * b.area);
  EXPECT_NEAR(a.mean_curvature, b.mean_curvature, 1e-9);
  EXPECT_NEAR(a.mean_curvature_std, b.mean_curvature_std, 1e-9);
  EXPECT_NEAR(a.gaussian_curvature_integral, b.gaussian_curvature_integral,
              1e-9 * std::abs(b.gaussian_curvature_integral));
  EXPECT_NEAR(a.willmore_energy, b.willmore_energy, 1e-9 * b.willmore_energy);
}

TEST(SharpSurface, GaussianCurvatureOfABallConvergesAndMeetsGaussBonnet) {
  // K = 1/r^2 everywhere on a sphere; its integral 4 pi = 2 pi chi (a sphere, chi 2), and the
  // Willmore energy integral H^2 dA = 4 pi for any radius.
  const double r = 0.3, eps = 0.01;
  double err[2];
  const int grids[2] = {32, 64};
  for (int g = 0; g < 2; ++g) {
    const SharpMeasures m = sharp_measures(tanh_ball(grids[g], r, eps));
    err[g] = std::abs(m.gaussian_curvature_integral / (4 * kPi) - 1.0);
    EXPECT_NEAR(m.willmore_energy, 4 * kPi, 2e-2 * 4 * kPi) << grids[g];
  }
  // Second order: 64^3 within 1e-3 (a sphere of 19 cells' radius), and the error falls ~4x.
  EXPECT_LT(err[1], 1e-3);
  EXPECT_GT(std::log2(err[0] / err[1]), 1.5);
}

TEST(SharpSurface, GaussianCurvatureOfACylinderAndOfPlanesVanishes) {
  const double r = 0.25;
  const Field cylinder = sample(64, [=](double x, double y, double) {
    return tanh_profile(r - std::hypot(x - 0.5, y - 0.5), 0.01);
  });
  std::vector<CurvatureSample> samples;
  const SharpMeasures m = sharp_measures(cylinder, &samples);
  // Flat along the axis: K = 0 up to the O(h^2) error of H^2-sized terms (1/r^2 = 16).
  EXPECT_NEAR(m.gaussian_curvature_integral / m.area, 0.0, 1e-3 / (r * r));
  EXPECT_NEAR(m.willmore_energy, m.area * 0.25 / (r * r), 2e-3 * m.willmore_energy);
  double worst = 0.0;
  for (const CurvatureSample& s : samples) worst = std::max(worst, std::abs(s.k));
  EXPECT_LT(worst * r * r, 0.02);
}

TEST(SharpSurface, GaussBonnetOnATorusAndAGyroidLevelSet) {
  // A torus of radii 0.3 and 0.1 (chi 0) and the gyroid level set F = 0 (chi -8 per cell:
  // genus 5) from their level-set functions, not from a tanh profile: K integrates to 2 pi chi.
  const Field torus = sample(64, [](double x, double y, double z) {
    const double q = std::hypot(x - 0.5, y - 0.5) - 0.3;
    return 0.1 - std::hypot(q, z - 0.5);
  });
  const LevelSetSurface t = level_set_surface(torus);
  // Within 1 % of the integral of |K|, 8 pi for any torus.
  EXPECT_NEAR(t.gaussian_curvature_integral, 0.0, 1e-2 * 8 * kPi);
  const Field gyroid = sample(64, [](double x, double y, double z) {
    const double w = 2 * kPi;
    return std::sin(w * x) * std::cos(w * y) + std::sin(w * y) * std::cos(w * z) +
           std::sin(w * z) * std::cos(w * x);
  });
  const LevelSetSurface g = level_set_surface(gyroid);
  EXPECT_NEAR(g.gaussian_curvature_integral / (2 * kPi * -8.0), 1.0, 5e-3);
}

TEST(SharpSurface, TanhProfileInverseIsTheScaledDistance) {
  const double eps = 0.02;
  const Field phi = sample(
      32, [=](double x, double, double) { return tanh_profile(0.1 * std::sin(2 * kPi * x), eps); });
  Field psi = Field::like(phi, 2);
  tanh_profile_inverse(phi, psi);
  for (int i = 0; i < 32; ++i) {
    const double d = 0.1 * std::sin(2 * kPi * (i + 0.5) / 32);
    EXPECT_NEAR(psi(i, 3, 5), d / (2 * std::numbers::sqrt2 * eps), 1e-9);
  }
  EXPECT_EQ(psi(-1, 3, 5), psi(31, 3, 5));  // halo exchanged
  EXPECT_EQ(psi(1, 3, -2), psi(1, 3, 30));
}

TEST(SharpSurface, RefusesANarrowHalo) {
  Field psi(16, 1);
  EXPECT_THROW(level_set_surface(psi), std::invalid_argument);
}

}  // namespace
}  // namespace cmcsurf
