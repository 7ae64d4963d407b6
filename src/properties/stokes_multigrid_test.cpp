// The velocity multigrid: its fine level is the Stokes operator's velocity block, each coarse
// level half the Galerkin product of the finer one (against a plain twin), the cycle is a
// symmetric positive definite preconditioner, and exact where the fine grid is the coarsest.
#include "properties/stokes_multigrid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "properties/solid_fraction.h"
#include "properties/operator_testing.h"

namespace cmcsurf::properties {
namespace {

using testing::random_clamped_solid;

// Plain vectors, as the multigrid takes them.
std::vector<double> random_values(std::size_t m, unsigned seed) {
  return testing::random_vec<std::vector<double>>(m, seed);
}

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0.0;
  for (std::size_t q = 0; q < a.size(); ++q) s += a[q] * b[q];
  return s;
}

// Level 0 is A / mu + sigma on the fluid faces: the operator's plain twin with p = 0.
TEST(VelocityMultigrid, FineLevelIsTheVelocityBlock) {
  for (int n : {6, 7}) {
    const auto s = random_clamped_solid(n, 3 + n);
    const double mu = 2.5, sigma = 0.03;
    const StokesOperator op(n, s, mu);
    const VelocityMultigrid mg(op, sigma);
    const std::size_t m = op.cells();
    std::vector<double> x = random_values(op.size(), 11), y(op.size());
    for (std::size_t q = 3 * m; q < 4 * m; ++q) x[q] = 0.0;
    op.apply_ref(x.data(), y.data());
    for (int c = 0; c < 3; ++c) {
      std::vector<double> yl(m);
      mg.apply_level(0, c, x.data() + c * m, yl.data());
      for (std::size_t q = 0; q < m; ++q) {
        const double expect =
            op.fluid_face(c, q) ? y[c * m + q] / mu + sigma * x[c * m + q] : 0.0;
        // The operator's diagonal is stored in single precision.
        EXPECT_NEAR(yl[q], expect, 1e-6 * (1.0 + std::abs(expect))) << n << " " << c << " " << q;
      }
    }
  }
}

// Each coarse level equals 1/2 P^T A P of the finer one (P piecewise constant on the 2 x 2 x 2
// aggregates, the odd sizes' last layer alone), to the single precision of its stored stencil.
TEST(VelocityMultigrid, CoarseLevelsAreHalfTheGalerkinProduct) {
  for (int n : {12, 13}) {
    const StokesOperator op(n, random_clamped_solid(n, 5 + n));
    const VelocityMultigrid mg(op, 0.01);
    ASSERT_EQ(mg.levels(), 3);
    EXPECT_EQ(mg.level_n(1), (n + 1) / 2);
    EXPECT_EQ(mg.level_n(2), (mg.level_n(1) + 1) / 2);
    for (int l = 1; l < mg.levels(); ++l)
      for (int c = 0; c < 3; ++c) {
        const std::size_t mc = std::size_t(mg.level_n(l)) * mg.level_n(l) * mg.level_n(l);
        const auto x = random_values(mc, 7 + l + c);
        std::vector<double> y(mc), y_ref(mc);
        mg.apply_level(l, c, x.data(), y.data());
        mg.apply_level_ref(l, c, x.data(), y_ref.data());
        double big = 0.0, diff = 0.0;
        for (std::size_t q = 0; q < mc; ++q) {
          big = std::max(big, std::abs(y_ref[q]));
          diff = std::max(diff, std::abs(y[q] - y_ref[q]));
        }
        EXPECT_GT(big, 0.0);
        EXPECT_LT(diff, 1e-6 * big) << "n " << n << " level " << l << " component " << c;
      }
  }
}

// MINRES needs a fixed symmetric positive definite preconditioner.
TEST(VelocityMultigrid, CycleIsSymmetricPositiveDefinite) {
  for (int n : {16, 18}) {
    const auto s = n == 16 ? nodal_gyroid_solid_fraction(n, GyroidSolid::network, 0.7)
                           : random_clamped_solid(n, 9);
    const StokesOperator op(n, s);
    for (int cycles : {1, 2}) {
      VelocityMultigridOptions o;
      o.cycles = cycles;
      const VelocityMultigrid mg(op, 0.02, o);
      const std::size_t m3 = 3 * op.cells();
      auto x = random_values(m3, 1), y = random_values(m3, 2);
      for (std::size_t q = 0; q < m3; ++q)
        if (!op.fluid_face(int(q / op.cells()), q % op.cells())) x[q] = y[q] = 0.0;
      std::vector<double> mx(m3), my(m3);
      mg.apply(x.data(), mx.data());
      mg.apply(y.data(), my.data());
      const double xmy = dot(x, my), ymx = dot(y, mx);
      EXPECT_NEAR(xmy, ymx, 1e-11 * dot(x, mx)) << n << " " << cycles;
      EXPECT_GT(dot(x, mx), 0.0);
      EXPECT_GT(dot(y, my), 0.0);
    }
  }
}

// n <= 4 is its own coarsest level: the cycle is the exact inverse.
TEST(VelocityMultigrid, SolvesTheCoarsestGridExactly) {
  const int n = 4;
  const StokesOperator op(n, random_clamped_solid(n, 21));
  const VelocityMultigrid mg(op, 0.05);
  ASSERT_EQ(mg.levels(), 1);
  const std::size_t m = op.cells();
  auto r = random_values(3 * m, 4);
  std::vector<double> z(3 * m), back(m);
  mg.apply(r.data(), z.data());
  for (int c = 0; c < 3; ++c) {
    mg.apply_level(0, c, z.data() + c * m, back.data());
    for (std::size_t q = 0; q < m; ++q)
      EXPECT_NEAR(back[q], op.fluid_face(c, q) ? r[c * m + q] : 0.0, 1e-10);
  }
}

TEST(VelocityMultigrid, RefusesBadOptions) {
  const StokesOperator op(4, random_clamped_solid(4, 1));
  EXPECT_THROW(VelocityMultigrid(op, 0.0), std::invalid_argument);
  VelocityMultigridOptions o;
  o.omega = 1.2;
  EXPECT_THROW(VelocityMultigrid(op, 0.1, o), std::invalid_argument);
}

}  // namespace
}  // namespace cmcsurf::properties
