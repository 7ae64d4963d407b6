// The directional Young's modulus surface against closed forms: constant for an isotropic
// solid; for a cubic tensor 1/E(d) = S11 - 2 (S11 - S12 - S44/2)(l^2 m^2 + m^2 n^2 + n^2 l^2)
// with its extremes on <100> and <111>.
#include "properties/directional_modulus.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "properties/cell_properties.h"

namespace cmcsurf::properties {
namespace {

double cubic_closed_form(const Matrix6& s, const Vector3& d) {
  const double l2 = d[0] * d[0], m2 = d[1] * d[1], n2 = d[2] * d[2];
  return 1.0 / (s[0][0] - 2.0 * (s[0][0] - s[0][1] - 0.5 * s[3][3]) *
                              (l2 * m2 + m2 * n2 + n2 * l2));
}

Matrix6 cubic_stiffness(double c11, double c12, double c44) {
  Matrix6 c{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) c[i][j] = i == j ? c11 : c12;
    c[i + 3][i + 3] = c44;
  }
  return c;
}

TEST(DirectionalModulus, IsotropicSurfaceIsTheSphereOfTheSolid) {
  const auto e = elastic_constants(isotropic_stiffness(0.3));
  const auto s = directional_youngs_surface(e.compliance_voigt, 8);
  ASSERT_EQ(s.directions.size(), 6u * 9u * 9u);
  ASSERT_EQ(s.triangles.size(), 6u * 8u * 8u * 2u);
  for (std::size_t i = 0; i < s.modulus.size(); ++i) {
    // E = E_s in every direction, to the 1e-10 max|C| that elastic_constants adds to C's
    // diagonal before inverting (3e-10 here).
    EXPECT_NEAR(s.modulus[i], 1.0, 1e-9);
    // A sphere's normal is its direction (central differences of a quartic: O(h^2) = 1e-10).
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(s.normals[i][a], s.directions[i][a], 1e-8);
  }
}

// The network gyroid's constants (docs/properties.md, 64^3: C11, C12, C44 = 0.1043, 0.0515,
// 0.0433, Zener 1.64) and a soft-shear crystal (Zener 0.4): every vertex equals the closed
// form, the extremes are the <100> and <111> values and lie along those directions.
TEST(DirectionalModulus, CubicTensorMatchesTheClosedFormWithExtremesOn100And111) {
  for (const auto& [c11, c12, c44] : {std::array<double, 3>{0.104321, 0.051523, 0.043287},
                                      std::array<double, 3>{2.0, 1.0, 0.2}}) {
    const auto e = elastic_constants(cubic_stiffness(c11, c12, c44));
    const Matrix6& sv = e.compliance_voigt;
    const auto s = directional_youngs_surface(sv, 10);
    for (std::size_t i = 0; i < s.modulus.size(); ++i)
      EXPECT_NEAR(s.modulus[i], cubic_closed_form(sv, s.directions[i]), 1e-12 * s.modulus[i]);
    const double e100 = 1.0 / sv[0][0];
    const double e111 = cubic_closed_form(sv, {1 / std::sqrt(3.0), 1 / std::sqrt(3.0),
                                               1 / std::sqrt(3.0)});
    const auto [lo, hi] = std::minmax_element(s.modulus.begin(), s.modulus.end());
    const bool stiff_diagonal = e.zener_ratio > 1.0;  // A > 1: E largest along <111>
    EXPECT_NEAR(*lo, stiff_diagonal ? e100 : e111, 1e-12 * *lo);
    EXPECT_NEAR(*hi, stiff_diagonal ? e111 : e100, 1e-12 * *hi);
    const Vector3& d_hi = s.directions[std::size_t(hi - s.modulus.begin())];
    const double largest = std::max({std::abs(d_hi[0]), std::abs(d_hi[1]), std::abs(d_hi[2])});
    EXPECT_NEAR(largest, stiff_diagonal ? 1 / std::sqrt(3.0) : 1.0, 1e-12);
    // The library's own search for the extremes agrees with the surface's vertices.
    EXPECT_NEAR(e.youngs_modulus_max, *hi, 1e-8 * *hi);
    EXPECT_NEAR(e.youngs_modulus_min, *lo, 1e-8 * *lo);
  }
}

TEST(DirectionalModulus, NormalsPointOutwardsAndTrianglesFaceOut) {
  const auto e = elastic_constants(cubic_stiffness(2.0, 1.0, 1.5));
  const auto s = directional_youngs_surface(e.compliance_voigt, 6);
  for (std::size_t i = 0; i < s.normals.size(); ++i) {
    const auto& n = s.normals[i];
    const auto& d = s.directions[i];
    EXPECT_NEAR(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 1.0, 1e-12);
    EXPECT_GT(n[0] * d[0] + n[1] * d[1] + n[2] * d[2], 0.0);
  }
  for (const auto& t : s.triangles) {  // (b - a) x (c - a) points away from the origin
    Vector3 p[3];
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a) p[k][a] = s.modulus[t[k]] * s.directions[t[k]][a];
    const Vector3 u{p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
    const Vector3 v{p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
    const Vector3 c{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                    u[0] * v[1] - u[1] * v[0]};
    EXPECT_GT(c[0] * p[0][0] + c[1] * p[0][1] + c[2] * p[0][2], 0.0);
  }
  EXPECT_THROW(directional_youngs_surface(e.compliance_voigt, 3), std::invalid_argument);
}

}  // namespace
}  // namespace cmcsurf::properties
