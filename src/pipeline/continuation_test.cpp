#include "pipeline/continuation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "../../tests/test_fields.h"
#include "measure/measures.h"

namespace cmcsurf {
namespace {

using testing::max_abs_diff;
using testing::sample_at_centres;

// The equilibrium profile of a slab 0.25 < x < 0.75 (two planar interfaces), epsilon eps.
double slab(double x, double eps) {
  const double d = 0.25 - std::abs(x - 0.5);  // signed distance, positive inside
  return 0.5 * (1.0 + std::tanh(d / (2.0 * std::sqrt(2.0) * eps)));
}

TEST(Continuation, ProfileProlongationKeepsTheTanhProfile) {
  const int n = 32;
  const double eps = 0.64 / n;  // the 64^3 default's epsilon/h: the layer is two cells wide
  auto exact = [&](double x, double, double) { return slab(x, eps); };
  const Field coarse = sample_at_centres(n, 2, exact);
  const Field fine_exact = sample_at_centres(2 * n, 2, exact);
  Field trilinear(2 * n, 2), profile(2 * n, 2);
  prolongate_trilinear(coarse, trilinear);
  prolongate_profile(coarse, profile);
  // psi is linear across a plane's layer, so its interpolation is exact there; the bulk cells
  // (|2 phi - 1| > 0.999) are interpolated linearly, off by at most their curvature, and the
  // mean-restoring constant is of the same size.
  const double e_trilinear = max_abs_diff(trilinear, fine_exact);
  const double e_profile = max_abs_diff(profile, fine_exact);
  // Measured 0.0106: averaging the steep tanh across two coarse cells.
  EXPECT_GT(e_trilinear, 0.01);
  EXPECT_LT(e_profile, 1e-3);
  EXPECT_LT(e_profile, e_trilinear / 50);
}

TEST(Continuation, ProfileProlongationKeepsTheMeanAndTheBulk) {
  const int n = 16;
  // A curved interface (a ball) with bulk values off 0 and 1, as a relaxed field has them.
  const Field coarse = sample_at_centres(n, 2, [](double x, double y, double z) {
    const double r = std::hypot(x - 0.5, y - 0.5, z - 0.5);
    return 1.002 * 0.5 * (1.0 - std::tanh((r - 0.3) / 0.05)) - 0.001;
  });
  Field fine(2 * n, 2), trilinear(2 * n, 2);
  prolongate_profile(coarse, fine);
  prolongate_trilinear(coarse, trilinear);
  EXPECT_NEAR(mass(fine), mass(coarse), 1e-15);
  // Far from the ball (phi outside [0, 1] here, as a relaxed field's bulk is) the cells are
  // interpolated linearly and the mass correction, which lives in the layer, leaves them alone.
  EXPECT_NEAR(fine(0, 0, 0), trilinear(0, 0, 0), 1e-15);
  EXPECT_NEAR(fine(1, 2, 3), trilinear(1, 2, 3), 1e-15);
}

TEST(Continuation, GeometricSeriesSettleWhenTheirTailIsSmall) {
  // x_n = 1 - 0.5^n: the tail after x_n is exactly 0.5^n = |d_n|.
  std::vector<double> x;
  int settled_at = -1;
  for (int n = 0; n < 40 && settled_at < 0; ++n) {
    x.push_back(1.0 - std::pow(0.5, n));
    if (series_settled(x, 1e-6)) settled_at = n;
  }
  EXPECT_EQ(settled_at, 20);  // 0.5^20 = 9.5e-7 <= 1e-6 < 0.5^19
  EXPECT_FALSE(series_settled(std::vector<double>{1.0, 2.0, 3.0}, 1e9));  // fewer than four
  EXPECT_TRUE(series_settled(std::vector<double>{1.0, 2.0, 3.0, 3.0}, 0.0));  // no change
}

TEST(Continuation, SteadyDriftNeverSettles) {
  // A neck narrowing at a constant or growing rate, however slowly, has no finite tail.
  EXPECT_FALSE(series_settled(std::vector<double>{1.0, 1.0 - 1e-9, 1.0 - 2e-9, 1.0 - 3e-9}, 1e-3));
  EXPECT_FALSE(series_settled(std::vector<double>{1.0, 1.0 - 1e-9, 1.0 - 3e-9, 1.0 - 7e-9}, 1e-3));
  // A change that reverses and grows again has not settled either.
  EXPECT_FALSE(series_settled(std::vector<double>{1.0, 1.0 + 4e-9, 1.0 + 5e-9, 1.0 + 3e-9}, 1e-3));
  // Shrinking at ratio 0.9: the tail is 9 times the last change.
  const std::vector<double> slow{0.0, 1e-6, 1.9e-6, 2.71e-6};
  EXPECT_FALSE(series_settled(slow, 7e-6));
  EXPECT_TRUE(series_settled(slow, 7.4e-6));
}

}  // namespace
}  // namespace cmcsurf
