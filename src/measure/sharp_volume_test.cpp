#include "measure/sharp_volume.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <numbers>
#include <random>

#include "../../tests/test_fields.h"
#include "measure/measures.h"

namespace cmcsurf {
namespace {

using testing::kPi;

using testing::sample_at_centres;

// Fraction of the tetrahedron where sum_a lambda_a g_a > 0, by the midpoint rule on the
// subdivision of the barycentric simplex into m^3 small simplices (counted by lattice points).
double tet_fraction_by_quadrature(const double g[4], int m) {
  long above = 0, total = 0;
  for (int a = 0; a < m; ++a)
    for (int b = 0; a + b < m; ++b)
      for (int c = 0; a + b + c < m; ++c) {
        // Points of a finer lattice inside: a rough but unbiased sampling.
        const double l1 = (a + 0.25) / m, l2 = (b + 0.25) / m, l3 = (c + 0.25) / m;
        const double l0 = 1.0 - l1 - l2 - l3;
        ++total;
        if (l0 * g[0] + l1 * g[1] + l2 * g[2] + l3 * g[3] > 0.0) ++above;
      }
  return double(above) / double(total);
}

TEST(SharpVolume, TetFractionClosedForms) {
  const double one[4] = {1, -1, -1, -1};  // one vertex above, each edge cut at its middle
  EXPECT_DOUBLE_EQ(tet_fraction_above(one), 0.125);
  const double three[4] = {1, 1, -1, 1};
  EXPECT_DOUBLE_EQ(tet_fraction_above(three), 0.875);
  const double two[4] = {1, -1, 1, -1};  // the mid-plane between two opposite edges
  EXPECT_DOUBLE_EQ(tet_fraction_above(two), 0.5);
  const double all[4] = {0.1, 0.2, 0.3, 0.4}, none[4] = {0, -0.2, 0, -0.4};
  EXPECT_EQ(tet_fraction_above(all), 1.0);
  EXPECT_EQ(tet_fraction_above(none), 0.0);  // 0 is not above: phase 1 is phi > 1/2 strictly
}

// Random vertex values: the closed form matches quadrature, is the complement of the fraction
// of -g, and does not depend on the order of the vertices.
TEST(SharpVolume, TetFractionMatchesQuadrature) {
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 60; ++trial) {
    double g[4], minus[4];
    for (int a = 0; a < 4; ++a) {
      g[a] = u(gen);
      minus[a] = -g[a];
    }
    const double f = tet_fraction_above(g);
    // Quadrature with 200^3/6 points: error ~ (surface lattice points) / total ~ 3/200.
    EXPECT_NEAR(f, tet_fraction_by_quadrature(g, 200), 0.015) << trial;
    EXPECT_NEAR(f + tet_fraction_above(minus), 1.0, 1e-14);
    const double perm[4] = {g[2], g[0], g[3], g[1]};
    EXPECT_NEAR(tet_fraction_above(perm), f, 1e-14);
  }
}

// The one-sweep estimator against its two passes (the corrected field, then the linear
// estimator), which add the same values in the same per-thread order: bit for bit, at 1 and 2
// threads, on noise (cut cells everywhere), a gyroid and a half-filled slab (whole rows of
// inside and outside cells), odd sizes included (uneven slabs).
// A run of inside cells added at once has the bits of the additions one by one, also where
// the run crosses a power of two from a sum with its lowest bit set (there one addition of
// 6 count would round differently: the second loop finds such cases).
TEST(SharpVolume, RunOfSixesAddsAsOneByOne) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int differ_at_once = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const int count = 1 + int(rng() % 40);
    // Just below a power of two (2^3 .. 2^40), with random low bits, or anywhere.
    const double p2 = std::ldexp(1.0, 3 + int(rng() % 38));
    const double sum = trial % 2 ? p2 - 6.0 * count * unit(rng) : p2 * (1.0 + unit(rng));
    double one_by_one = sum;
    for (int c = 0; c < count; ++c) one_by_one += 6.0;
    EXPECT_EQ(add_sixes(sum, count), one_by_one) << sum << " + 6 x " << count;
    if (sum + 6.0 * count != one_by_one) ++differ_at_once;
  }
  EXPECT_GT(differ_at_once, 50);  // where adding at once would change bits (96 with this seed)
}

TEST(SharpVolume, OneSweepMatchesTwoPassesBitForBit) {
  const int saved_threads = omp_get_max_threads();
  for (const int threads : {1, 2}) {
    omp_set_num_threads(threads);
    for (const int n : {12, kParallelMinN + 5}) {
      Field slab(n, 2);
      for_each_cell(slab, [&](int i, int j, int k) { slab(i, j, k) = k < n / 2 ? 0.9 : 0.1; });
      slab.exchange_halo();
      const Field fields[3] = {testing::random_field(n, 2, -0.2, 1.2, 7),
                               testing::gyroid_field(n, 2), slab};
      for (const Field& phi : fields) {
        Field psi(n, 1);
        curvature_corrected(phi, psi);
        const double two = linear_volume_fraction(psi);
        EXPECT_GT(two, 0.05);
        EXPECT_EQ(sharp_volume_fraction(phi), two) << "n " << n << " threads " << threads;
      }
    }
  }
  omp_set_num_threads(saved_threads);
}

TEST(SharpVolume, MatchesReferenceOnRandomField) {
  for (unsigned seed : {1u, 2u}) {
    const Field phi = testing::random_field(kParallelMinN + 8, 2, -0.2, 1.2, seed);
    EXPECT_NEAR(linear_volume_fraction(phi), linear_volume_fraction_ref(phi), 1e-13);
    EXPECT_NEAR(sharp_volume_fraction(phi), sharp_volume_fraction_ref(phi), 1e-13);
  }
  const Field g = testing::gyroid_field(24, 2);
  EXPECT_NEAR(linear_volume_fraction(g), linear_volume_fraction_ref(g), 1e-13);
  EXPECT_NEAR(sharp_volume_fraction(g), sharp_volume_fraction_ref(g), 1e-13);
}

// A slab a < x < b of phase 1 with linear ramps wider than the stencils: the interpolant is
// exact across the interfaces and the bias correction vanishes (zero second differences), so
// both measures are b - a to round-off, in every orientation.
TEST(SharpVolume, PlanarSlabIsExact) {
  const int n = 32;
  const double a = 0.2137, b = 0.6071, ramp = 0.3;
  auto slab = [=](double t) {
    const double d = std::min(t - a, b - t);  // signed distance, > 0 inside
    return std::clamp(0.5 + d / ramp, 0.0, 1.0);
  };
  for (int axis = 0; axis < 3; ++axis) {
    const Field phi = sample_at_centres(n, 2, [&](double x, double y, double z) {
      return slab(axis == 0 ? x : axis == 1 ? y : z);
    });
    // Round-off of a sum over N^3 dual cells: bound N^3 eps_machine ~ 7e-12, observed 2e-14.
    EXPECT_NEAR(linear_volume_fraction(phi), b - a, 1e-12) << "axis " << axis;
    EXPECT_NEAR(sharp_volume_fraction(phi), b - a, 1e-12) << "axis " << axis;
    // The cell count is off by a fraction of a cell per interface.
    EXPECT_GT(std::abs(volume_fraction(phi) - (b - a)), 1e-3);
  }
}

// G's nodal field is odd under x -> -x, which maps cell centres to cell centres and the Kuhn
// split onto itself: the sharp volume of G + 1/2 is exactly 1/2.
TEST(SharpVolume, OddFieldHasHalfVolume) {
  const int n = 20;
  const Field phi = sample_at_centres(n, 2, [](double x, double y, double z) {
    const double w = 2 * kPi;
    return 0.5 + std::sin(w * x) * std::cos(w * y) + std::sin(w * z) * std::cos(w * x) +
           std::sin(w * y) * std::cos(w * z);
  });
  EXPECT_NEAR(linear_volume_fraction(phi), 0.5, 1e-14);
  EXPECT_NEAR(sharp_volume_fraction(phi), 0.5, 1e-14);
}

// The phi = 1/2 level of the tanh sphere is the sphere of radius r, at any epsilon. Under
// refinement with fixed epsilon the plain interpolant converges at second order (its error is
// the O(kappa h^2) chord bias, independent of epsilon); the corrected estimator removes that
// term (measured errors 9.2e-5, 6.8e-6, 5.5e-7: order ~3.7).
TEST(SharpVolume, TanhSphereConverges) {
  const double r = 0.3, epsilon = 0.02, exact = 4.0 / 3.0 * kPi * r * r * r;
  double lin[3], sharp[3];
  const int grids[3] = {32, 64, 128};
  for (int g = 0; g < 3; ++g) {
    const Field phi = sample_at_centres(grids[g], 2, [=](double x, double y, double z) {
      const double d = std::sqrt((x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5) +
                                 (z - 0.5) * (z - 0.5));
      return 0.5 * (1.0 + std::tanh((r - d) / (2.0 * std::numbers::sqrt2 * epsilon)));
    });
    lin[g] = std::abs(linear_volume_fraction(phi) - exact);
    sharp[g] = std::abs(sharp_volume_fraction(phi) - exact);
  }
  for (int g = 0; g < 2; ++g) {
    // Observed orders log2(err[g] / err[g + 1]): 2.02 and 2.00 for the plain interpolant.
    EXPECT_NEAR(std::log2(lin[g] / lin[g + 1]), 2.0, 0.1) << lin[g] << " " << lin[g + 1];
    EXPECT_GT(std::log2(sharp[g] / sharp[g + 1]), 3.0) << sharp[g] << " " << sharp[g + 1];
    EXPECT_LT(sharp[g], 0.2 * lin[g]);
  }
  EXPECT_LT(sharp[1], 1e-5);  // at 64^3, a tenth of the 1e-4 default of --volume-tol
}

// On smooth random fields the sharp measure and the cell count agree to within the cell
// count's O(h) error: they can differ only in cells next to the interface.
TEST(SharpVolume, AgreesWithCellCountToCellCountAccuracy) {
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 3; ++trial) {
    double amp[4], ph[4][3];
    for (int m = 0; m < 4; ++m) {
      amp[m] = 0.3 * u(gen);
      for (int d = 0; d < 3; ++d) ph[m][d] = kPi * u(gen);
    }
    const double offset = 0.5 + 0.1 * u(gen);
    const int n = 32;
    const Field phi = sample_at_centres(n, 2, [&](double x, double y, double z) {
      double v = offset;
      for (int m = 0; m < 4; ++m)
        v += amp[m] * std::cos(2 * kPi * ((m % 2 + 1) * x + ph[m][0])) *
             std::cos(2 * kPi * ((m / 2 + 1) * y + ph[m][1])) *
             std::cos(2 * kPi * (z + ph[m][2]));
      return v;
    });
    long interface_cells = 0;
    for_each_cell(n, [&](int i, int j, int k) {
      const bool in = phi(i, j, k) > 0.5;
      if ((phi(i + 1, j, k) > 0.5) != in || (phi(i - 1, j, k) > 0.5) != in ||
          (phi(i, j + 1, k) > 0.5) != in || (phi(i, j - 1, k) > 0.5) != in ||
          (phi(i, j, k + 1) > 0.5) != in || (phi(i, j, k - 1) > 0.5) != in)
        ++interface_cells;
    });
    const double band = double(interface_cells) / phi.interior_size();
    const double diff = std::abs(sharp_volume_fraction(phi) - volume_fraction(phi));
    EXPECT_GT(band, 0.0);
    EXPECT_LT(diff, 0.5 * band) << "trial " << trial;
  }
}

}  // namespace
}  // namespace cmcsurf
