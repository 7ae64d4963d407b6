#include "science/scattering.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "surfaces/nodal_level.h"
#include "../../tests/test_fields.h"

namespace cmcsurf {
namespace {

using testing::kPi;

// A tanh ball of radius r centred at (1/2, 1/2, 1/2), a corner of the cells.
Field ball(int n, double r, double w) {
  Field phi(n, 2);
  for (int k = -2; k < n + 2; ++k)
    for (int j = -2; j < n + 2; ++j)
      for (int i = -2; i < n + 2; ++i) {
        const double x = (i + 0.5) / n - 0.5, y = (j + 0.5) / n - 0.5, z = (k + 0.5) / n - 0.5;
        phi(i, j, k) = 0.5 * (1 + std::tanh((r - std::sqrt(x * x + y * y + z * z)) / w));
      }
  return phi;
}

std::vector<Reflection> classes_of(const Field& phi, const std::string& model, int smax) {
  const StructureFactors f(density_from_phase_field(phi, parse_density_model(model)));
  return reflection_classes(f, smax, 1e-8);
}

const Reflection& find(const std::vector<Reflection>& c, int h, int k, int l) {
  for (const auto& r : c)
    if (r.h == h && r.k == k && r.l == l) return r;
  throw std::logic_error("no such class");
}

// At 0.5 the level F = 0 exactly (nodal_level_set finds it to 1e-7), so that the two
// labyrinths are congruent to round-off.
Field nodal_profile(const std::string& surface, double alpha, int n) {
  NodalLevelSet nodal = nodal_level_set(surface, alpha, n);
  if (alpha == 0.5) nodal.level = 0.5;
  return nodal_tanh_profile(nodal, 0.02);
}

// The step density's F of a ball against the sphere's form factor
// V 3 (sin x - x cos x) / x^3, x = 2 pi r |q|, times (-1)^(h+k+l) for the centre at 1/2.
TEST(Scattering, BallMatchesSphereFormFactor) {
  const double r = 0.3;
  const double volume = 4.0 / 3.0 * kPi * r * r * r;
  double worst32 = 0, worst48 = 0;
  for (int n : {32, 48}) {
    const StructureFactors f(density_from_phase_field(ball(n, r, 0.03), {}));
    double worst = std::abs(f(0, 0, 0).real() - volume);
    for (int h = -4; h <= 4; ++h)
      for (int k = -4; k <= 4; ++k)
        for (int l = -4; l <= 4; ++l) {
          const int s = h * h + k * k + l * l;
          if (s == 0 || s > 16) continue;
          const double x = 2 * kPi * r * std::sqrt(double(s));
          const double exact = volume * 3 * (std::sin(x) - x * std::cos(x)) / (x * x * x) *
                               ((h + k + l) % 2 == 0 ? 1 : -1);
          worst = std::max(worst, std::abs(f(h, k, l) - exact));
        }
    (n == 32 ? worst32 : worst48) = worst / volume;
  }
  // Measured 1.6e-3 and 4.8e-4 of F_000: third order in h (the step's aliased F_{h+mN}).
  EXPECT_LT(worst32, 2.5e-3);
  EXPECT_LT(worst48, 7e-4);
  EXPECT_LT(worst48, worst32 / 3);
}

// A G sheet (bilayer around the surface at 0.5): Ia-3d, (110) and (200) vanish to round-off.
TEST(Scattering, GyroidBilayerAbsences) {
  const auto c = classes_of(nodal_profile("G", 0.5, 32), "bilayer:0.05", 24);
  const double strongest = find(c, 2, 1, 1).intensity;
  EXPECT_LT(find(c, 1, 1, 0).intensity, 1e-20 * strongest);
  EXPECT_LT(find(c, 2, 0, 0).intensity, 1e-20 * strongest);
  EXPECT_LT(find(c, 2, 2, 2).intensity, 1e-20 * strongest);
  EXPECT_GT(find(c, 2, 2, 0).intensity, 1e-3 * strongest);
  EXPECT_TRUE(find(c, 2, 1, 1).present);
  EXPECT_TRUE(find(c, 2, 2, 0).present);
  const SpaceGroupFit fit = detect_space_group(c);
  EXPECT_STREQ(fit.best->symbol, "Ia-3d");
}

// One gyroid labyrinth (phase 1 at 0.3): I4_132, (110) present, (200) absent.
TEST(Scattering, SingleGyroidNetwork) {
  const auto c = classes_of(nodal_profile("G", 0.3, 32), "step", 24);
  EXPECT_TRUE(find(c, 1, 1, 0).present);
  EXPECT_FALSE(find(c, 2, 0, 0).present);
  EXPECT_STREQ(detect_space_group(c).best->symbol, "I4_132");
}

// D at 0.5, bilayer: the formula's cell holds 2^3 cells of the sheet (a translation by 1/2
// swaps the labyrinths), on which it is Pn-3m: (200) absent, (220), (222) present. One D
// labyrinth (step at 0.3): Fd-3m, (111), (220) present, (200), (110) absent. P: Im-3m.
TEST(Scattering, DiamondAndPrimitive) {
  const auto d = classes_of(nodal_profile("D", 0.5, 32), "bilayer:0.05", 24);
  EXPECT_FALSE(find(d, 2, 0, 0).present);
  EXPECT_FALSE(find(d, 1, 1, 1).present);
  EXPECT_TRUE(find(d, 2, 2, 0).present);
  EXPECT_TRUE(find(d, 2, 2, 2).present);
  const SpaceGroupFit fit = detect_space_group(d);
  EXPECT_EQ(fit.divisor, 2);
  EXPECT_STREQ(fit.best->symbol, "Pn-3m");
  const auto dn = classes_of(nodal_profile("D", 0.3, 32), "step", 24);
  EXPECT_TRUE(find(dn, 1, 1, 1).present);
  EXPECT_TRUE(find(dn, 2, 2, 0).present);
  EXPECT_FALSE(find(dn, 2, 0, 0).present);
  EXPECT_FALSE(find(dn, 1, 1, 0).present);
  EXPECT_STREQ(detect_space_group(dn).best->symbol, "Fd-3m");
  const auto p = classes_of(nodal_profile("P", 0.5, 32), "bilayer:0.05", 24);
  EXPECT_FALSE(find(p, 1, 0, 0).present);
  EXPECT_TRUE(find(p, 1, 1, 0).present);
  EXPECT_TRUE(find(p, 2, 0, 0).present);
  EXPECT_STREQ(detect_space_group(p).best->symbol, "Im-3m");
}

// Reflection conditions against hand-checked cases.
TEST(Scattering, ReflectionConditions) {
  const auto& ia3d = find_space_group("Ia-3d");
  EXPECT_FALSE(space_group_allows(ia3d, 1, 1, 0));
  EXPECT_TRUE(space_group_allows(ia3d, 2, 1, 1));
  EXPECT_TRUE(space_group_allows(ia3d, 2, 2, 0));
  EXPECT_FALSE(space_group_allows(ia3d, 2, 2, 2));
  EXPECT_TRUE(space_group_allows(ia3d, 3, 2, 1));
  EXPECT_TRUE(space_group_allows(ia3d, 4, 0, 0));
  EXPECT_FALSE(space_group_allows(ia3d, 3, 1, 0));
  const auto& fd3m = find_space_group("Fd-3m");
  EXPECT_TRUE(space_group_allows(fd3m, 1, 1, 1));
  EXPECT_FALSE(space_group_allows(fd3m, 2, 0, 0));
  EXPECT_TRUE(space_group_allows(fd3m, 2, 2, 0));
  EXPECT_FALSE(space_group_allows(fd3m, 4, 2, 0));
  EXPECT_TRUE(space_group_allows(fd3m, 3, 1, 1));
  const auto& pn3m = find_space_group("Pn-3m");
  EXPECT_FALSE(space_group_allows(pn3m, 1, 0, 0));
  EXPECT_TRUE(space_group_allows(pn3m, 1, 1, 1));
  EXPECT_FALSE(space_group_allows(pn3m, 2, 1, 0));
}

// Multiplicities of m-3m orbits.
TEST(Scattering, Multiplicities) {
  const auto c = classes_of(nodal_profile("P", 0.5, 16), "profile", 14);
  EXPECT_EQ(find(c, 1, 0, 0).multiplicity, 6);
  EXPECT_EQ(find(c, 1, 1, 0).multiplicity, 12);
  EXPECT_EQ(find(c, 1, 1, 1).multiplicity, 8);
  EXPECT_EQ(find(c, 2, 1, 0).multiplicity, 24);
  EXPECT_EQ(find(c, 3, 2, 1).multiplicity, 48);
}

// Synthetic G peaks at a = 12.5 nm with 0.1% noise: a recovered to 0.1%.
TEST(Scattering, IndexingRecoversLattice) {
  const double a = 12.5;
  const int s[] = {6, 8, 14, 16, 20};
  const double noise[] = {1e-3, -5e-4, 8e-4, -1e-3, 2e-4};
  std::vector<double> q;
  for (int i = 0; i < 5; ++i) q.push_back(2 * kPi * std::sqrt(double(s[i])) / a * (1 + noise[i]));
  const Indexing ix = index_peaks(q, find_space_group("Ia-3d"), 50);
  EXPECT_NEAR(ix.lattice, a, 1e-3 * a);
  EXPECT_EQ(ix.s, std::vector<int>(s, s + 5));
  EXPECT_THROW(index_peaks({1.0}, find_space_group("Ia-3d"), 50), std::invalid_argument);
  // Ratios no cubic lattice of Ia-3d gives.
  EXPECT_THROW(index_peaks({1.0, 1.05, 1.9}, find_space_group("Ia-3d"), 50, 1e-3),
               std::runtime_error);
}

// The whole analysis: the G sheet's group and its indexing; bad input refused.
TEST(Scattering, Analysis) {
  ScatteringParams p;
  p.density = parse_density_model("bilayer:0.05");
  p.powder.lattice = 10;
  for (int s : {6, 8, 14}) p.peaks.push_back(2 * kPi * std::sqrt(double(s)) / 10);
  const Field phi = nodal_profile("G", 0.5, 16);
  const ScatteringResult r = scattering_analysis(phi, p);
  EXPECT_EQ(r.smax, 49);  // (16/2 - 1)^2
  EXPECT_STREQ(r.space_group.best->symbol, "Ia-3d");
  EXPECT_NEAR(r.indexing.lattice, 10, 1e-9);
  EXPECT_FALSE(r.powder.q.empty());
  p.smax = 50;
  EXPECT_THROW(scattering_analysis(phi, p), std::invalid_argument);
  p.smax = 0;
  Field flat(16, 2);
  flat.fill(0.2);
  EXPECT_THROW(scattering_analysis(flat, p), std::invalid_argument);
}

TEST(Scattering, DensityModelParsing) {
  EXPECT_EQ(parse_density_model("bilayer:0.1").half_thickness, 0.1);
  EXPECT_THROW(parse_density_model("bilayer:0.3"), std::invalid_argument);
  EXPECT_THROW(parse_density_model("bilayer:"), std::invalid_argument);
  EXPECT_THROW(parse_density_model("sheet"), std::invalid_argument);
}

}  // namespace
}  // namespace cmcsurf
