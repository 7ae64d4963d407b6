// The Gibson-Ashby fit on exact power-law data returns its C and n to round-off.
#include "properties/power_law_fit.h"

#include <gtest/gtest.h>

#include <cmath>

namespace cmcsurf::properties {
namespace {

TEST(PowerLawFit, RecoversAnExactPowerLaw) {
  // ASLI's gyroid network law (E/E_s = 0.19 rho^1.71) and a stretch-dominated n = 1.
  for (const auto& [c, n] : {std::pair{0.19, 1.71}, std::pair{0.33, 1.0}}) {
    std::vector<double> rho, y;
    for (double r : {0.1, 0.2, 0.3, 0.45, 0.5}) {
      rho.push_back(r);
      y.push_back(c * std::pow(r, n));
    }
    const PowerLawFit f = fit_power_law(rho, y);
    ASSERT_TRUE(f.valid);
    EXPECT_EQ(f.points, 5);
    EXPECT_NEAR(f.exponent, n, 1e-12);  // logs of 5 numbers: round-off only
    EXPECT_NEAR(f.coefficient, c, 1e-12 * c);
    EXPECT_LT(f.rms_log_residual, 1e-13);
  }
}

TEST(PowerLawFit, ResidualOfKnownScatterAndPointsLeftOut) {
  // y = rho^2 times e^{+-0.1} alternately at two points per density: the least-squares line is
  // the exact law and every log residual is 0.1.
  std::vector<double> rho, y;
  for (double r : {0.2, 0.4, 0.8})
    for (double sign : {1.0, -1.0}) {
      rho.push_back(r);
      y.push_back(r * r * std::exp(0.1 * sign));
    }
  rho.push_back(0.5);  // zero stiffness (a member that does not percolate): left out
  y.push_back(0.0);
  rho.push_back(NAN);
  y.push_back(1.0);
  const PowerLawFit f = fit_power_law(rho, y);
  ASSERT_TRUE(f.valid);
  EXPECT_EQ(f.points, 6);
  EXPECT_NEAR(f.exponent, 2.0, 1e-12);
  EXPECT_NEAR(f.coefficient, 1.0, 1e-12);
  EXPECT_NEAR(f.rms_log_residual, 0.1, 1e-12);
}

TEST(PowerLawFit, OneDensityIsNoFit) {
  EXPECT_FALSE(fit_power_law({0.3, 0.3}, {0.1, 0.11}).valid);
  EXPECT_FALSE(fit_power_law({0.3}, {0.1}).valid);
  EXPECT_FALSE(fit_power_law({}, {}).valid);
  EXPECT_THROW(fit_power_law({0.3}, {}), std::invalid_argument);
}

}  // namespace
}  // namespace cmcsurf::properties
