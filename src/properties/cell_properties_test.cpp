// Engineering constants, Hashin-Shtrikman bounds, percolation and the assembled cell
// properties.
#include "properties/cell_properties.h"

#include <gtest/gtest.h>

#include <cmath>

#include "properties/solid_fraction.h"

namespace cmcsurf::properties {
namespace {

TEST(CellProperties, ConstantsOfTheIsotropicSolid) {
  const double nu = 0.3;
  const auto e = elastic_constants(isotropic_stiffness(nu));
  EXPECT_TRUE(e.invertible);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(e.youngs_modulus[a], 1.0, 1e-9);
    EXPECT_NEAR(e.shear_modulus[a], 1.0 / (2.0 * (1.0 + nu)), 1e-9);
    EXPECT_NEAR(e.poisson_ratio[a][(a + 1) % 3], nu, 1e-9);
  }
  EXPECT_NEAR(e.bulk_modulus, 1.0 / (3.0 * (1.0 - 2.0 * nu)), 1e-12);
  EXPECT_NEAR(e.zener_ratio, 1.0, 1e-12);
  EXPECT_NEAR(e.youngs_modulus_min, 1.0, 1e-9);
  EXPECT_NEAR(e.youngs_modulus_max, 1.0, 1e-9);
  // The bounds at full density are the solid itself.
  const auto b = hashin_shtrikman_upper(1.0, nu);
  EXPECT_NEAR(b.bulk_modulus, e.bulk_modulus, 1e-12);
  EXPECT_NEAR(b.shear_modulus, 1.0 / (2.0 * (1.0 + nu)), 1e-12);
  EXPECT_NEAR(b.youngs_modulus, 1.0, 1e-12);
  EXPECT_NEAR(b.conductivity, 1.0, 1e-12);
}

// Cubic crystal with Zener ratio A > 1: E is largest along <111> and smallest along <100>,
// E_111 from 1/E = S11 - 2 (S11 - S12 - S44 / 2) / 3.
TEST(CellProperties, DirectionalYoungsModulusOfACubicTensor) {
  Matrix6 c{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) c[i][j] = i == j ? 2.0 : 1.0;
    c[i + 3][i + 3] = 1.5;  // A = 2 * 1.5 / (2 - 1) = 3
  }
  const auto e = elastic_constants(c);
  EXPECT_NEAR(e.zener_ratio, 3.0, 1e-12);
  const Matrix6& s = e.compliance_voigt;
  const double e111 = 1.0 / (s[0][0] - 2.0 * (s[0][0] - s[0][1] - 0.5 * s[3][3]) / 3.0);
  EXPECT_NEAR(e.youngs_modulus_max, e111, 1e-8);
  EXPECT_NEAR(e.youngs_modulus_min, 1.0 / s[0][0], 1e-8);
  EXPECT_NEAR(std::abs(e.direction_max[0]), 1.0 / std::sqrt(3.0), 1e-4);
  const double axis = std::max({std::abs(e.direction_min[0]), std::abs(e.direction_min[1]),
                                std::abs(e.direction_min[2])});
  EXPECT_NEAR(axis, 1.0, 1e-6);
}

TEST(CellProperties, PercolationAlongAxes) {
  const int n = 8;
  std::vector<double> s(std::size_t(n) * n * n, 0.0);
  for (int k = 0; k < n; ++k)
    for (int j = 2; j < 4; ++j) s[(std::size_t(k) * n + j) * n + 5] = 1.0;  // a rod along z
  const auto p = percolating_axes(n, s);
  EXPECT_FALSE(p[0]);
  EXPECT_FALSE(p[1]);
  EXPECT_TRUE(p[2]);
  const auto g = percolating_axes(16, nodal_gyroid_solid_fraction(16, GyroidSolid::sheet, 0.7));
  EXPECT_TRUE(g[0] && g[1] && g[2]);
}

// Gyroid network and sheet: nothing exceeds its Hashin-Shtrikman bound; the pore's
// formation factor and tortuosity follow from its conductivity.
TEST(CellProperties, GyroidsStayBelowHashinShtrikman) {
  for (auto kind : {GyroidSolid::network, GyroidSolid::sheet}) {
    const int n = 16;
    const auto p = compute_cell_properties(n, nodal_gyroid_solid_fraction(n, kind, 0.7));
    EXPECT_NEAR(p.porosity, 0.7, 1e-9);
    EXPECT_TRUE(p.warnings.empty()) << p.warnings.front();
    EXPECT_GT(p.bulk_fraction_of_bound, 0.05);
    EXPECT_LT(p.bulk_fraction_of_bound, 1.0);
    EXPECT_LT(p.shear_fraction_of_bound, 1.0);
    EXPECT_LT(p.youngs_fraction_of_bound, 1.0);
    EXPECT_LT(p.conductivity_solid_fraction_of_bound, 1.0);
    EXPECT_LT(p.conductivity_pore_fraction_of_bound, 1.0);
    EXPECT_GT(p.conductivity_pore_fraction_of_bound, 0.3);
    const double kp = p.pore_conduction.conductivity[0][0];
    EXPECT_NEAR(p.formation_factor[0], 1.0 / kp, 1e-12);
    EXPECT_NEAR(p.tortuosity_pore[0], 0.7 / kp, 1e-9);
    EXPECT_GT(p.tortuosity_pore[0], 1.0);
    EXPECT_LE(p.constants.youngs_modulus_min, p.constants.youngs_modulus[0] + 1e-12);
    EXPECT_GE(p.constants.youngs_modulus_max, p.constants.youngs_modulus[0] - 1e-12);
  }
}

TEST(CellProperties, NonPercolatingSolidIsNamedInTheWarnings) {
  const int n = 8;
  std::vector<double> s(std::size_t(n) * n * n, 0.0);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 2; i < 5; ++i) s[(std::size_t(k) * n + j) * n + i] = 1.0;  // slabs normal to x
  const auto p = compute_cell_properties(n, s);
  ASSERT_EQ(p.warnings.size(), 2u);  // the void slabs between do not either
  EXPECT_EQ(p.warnings[0], "solid does not percolate along x");
  EXPECT_EQ(p.warnings[1], "pore space does not percolate along x");
  EXPECT_TRUE(p.elastic.converged && p.solid_conduction.converged);
  EXPECT_LT(p.constants.youngs_modulus[0], 1e-6);
  EXPECT_NEAR(p.constants.youngs_modulus[1], 3.0 / 8.0, 1e-6);  // a free plate, uniaxial
  EXPECT_NEAR(p.solid_conduction.conductivity[0][0], 0.0, 1e-8);
}

TEST(CellProperties, RestrictionAndRichardson) {
  const int n = 8;
  std::vector<double> s(std::size_t(n) * n * n);
  for (std::size_t e = 0; e < s.size(); ++e) s[e] = double(e % 5) / 4.0;
  const auto c = restrict_solid_fraction(n, s);
  double fine = 0.0, coarse = 0.0;
  for (double v : s) fine += v / s.size();
  for (double v : c) coarse += v / c.size();
  EXPECT_NEAR(coarse, fine, 1e-14);
  EXPECT_NEAR(richardson_limit(1.0, 1.5, 1.0), 0.5, 1e-15);
  EXPECT_NEAR(richardson_limit(1.0, 1.3, 2.0), 0.9, 1e-15);
}

// The wall shear stress of the flow along each axis: the gyroid network is invariant under the
// cyclic permutation x -> y -> z of the grid's axes, which maps the flows and their wall
// samples onto each other, so the three distributions agree to the solver's tolerance (1e-6
// relative on the preconditioned residual), and wall_shear is the z one.
TEST(CellProperties, WallShearStressAgreesAlongTheAxesOfACubicCell) {
  const int n = 16;
  CellPropertiesOptions o;
  o.elasticity = o.conductivity = false;
  o.flow = true;
  const CellProperties p =
      compute_cell_properties(n, nodal_gyroid_solid_fraction(n, GyroidSolid::network, 0.7), o);
  ASSERT_TRUE(p.flow.converged);
  const WallShearStats& z = p.wall_shear_axes[2];
  ASSERT_GT(z.mean, 0.0);
  EXPECT_EQ(p.wall_shear.mean, z.mean);
  for (int a = 0; a < 2; ++a) {
    const WallShearStats& w = p.wall_shear_axes[a];
    EXPECT_NEAR(w.wall_area, z.wall_area, 1e-9 * z.wall_area) << a;
    for (auto [got, want] : {std::pair{w.mean, z.mean}, {w.median, z.median}, {w.p5, z.p5},
                             {w.p95, z.p95}, {w.max, z.max}})
      EXPECT_NEAR(got, want, 1e-4 * z.mean) << "axis " << a;
  }
  // A slit along x and z (walls normal to y) has shear only for those two flows.
  std::vector<double> slit(std::size_t(n) * n * n, 0.0);
  for (std::size_t q = 0; q < slit.size(); ++q)
    if (q / n % n < 4) slit[q] = 1.0;
  const CellProperties ps = compute_cell_properties(n, slit, o);
  EXPECT_GT(ps.wall_shear_axes[0].mean, 0.0);
  EXPECT_EQ(ps.wall_shear_axes[1].wall_area, 0.0);
  EXPECT_NEAR(ps.wall_shear_axes[0].mean, ps.wall_shear_axes[2].mean,
              1e-6 * ps.wall_shear_axes[2].mean);
}

}  // namespace
}  // namespace cmcsurf::properties
