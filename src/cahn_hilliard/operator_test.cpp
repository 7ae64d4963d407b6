#include "cahn_hilliard/operator.h"

#include <gtest/gtest.h>

#include <fmt/format.h>
#include <omp.h>

#include <cmath>
#include <cstring>
#include <string>

#include "../../tests/test_fields.h"
#include "cahn_hilliard/time_step.h"
#include "multigrid/transfer.h"

namespace cmcsurf {
namespace {

using testing::max_abs_diff;
using testing::random_field;

const ChParams kParams{0.01, 0.5 / 32, SweepOrder::kRedBlack};

// The twins are compared at sizes >= kParallelMinN, where the kernels' loops run in parallel
// (CTest runs the *Reference* tests again with two threads).
constexpr int kTwinN = 32;
static_assert(kTwinN >= kParallelMinN);

TEST(CahnHilliard, ResidualMatchesReference) {
  const int n = kTwinN;
  Field phi = random_field(n, 1, 0, 1, 1), nu = random_field(n, 1, -0.1, 0.1, 2);
  Field r1 = random_field(n, 1, -10, 10, 3), r2 = random_field(n, 1, -1, 1, 4);
  Field a1(n, 1), a2(n, 1), b1(n, 1), b2(n, 1);
  nso_residual(phi, nu, &r1, &r2, kParams, a1, a2);
  nso_residual_ref(phi, nu, &r1, &r2, kParams, b1, b2);
  // Values reach ~ |nu|/h^2 ~ 1e2; the two differ only in summation order.
  EXPECT_LE(max_abs_diff(a1, b1), 1e-10);
  EXPECT_LE(max_abs_diff(a2, b2), 1e-12);
  nso_residual(phi, nu, nullptr, nullptr, kParams, a1, a2);
  nso_residual_ref(phi, nu, nullptr, nullptr, kParams, b1, b2);
  EXPECT_LE(max_abs_diff(a1, b1), 1e-10);
  EXPECT_LE(max_abs_diff(a2, b2), 1e-12);
}

TEST(CahnHilliard, ResidualNormMatchesReference) {
  const int n = kTwinN;
  Field phi = random_field(n, 1, 0, 1, 1), nu = random_field(n, 1, -0.1, 0.1, 2);
  Field r1 = random_field(n, 1, -10, 10, 3), r2 = random_field(n, 1, -1, 1, 4);
  const double fused = nso_residual_norm(phi, nu, r1, r2, kParams);
  const double ref = nso_residual_norm_ref(phi, nu, r1, r2, kParams);
  EXPECT_GT(fused, 0.1);
  EXPECT_NEAR(fused, ref, 1e-12 * ref);  // summation order only
  // The same bits as the defect written and its norm taken (the paper-faithful path's stop
  // test must not move).
  Field d1(n, 1), d2(n, 1);
  nso_residual(phi, nu, &r1, &r2, kParams, d1, d2);
  EXPECT_EQ(fused, ch_defect_norm(d1, d2, kParams.dt));
}

TEST(CahnHilliard, ResidualRestrictionMatchesReference) {
  const int n = kTwinN;
  Field phi = random_field(n, 1, 0, 1, 1), nu = random_field(n, 1, -0.1, 0.1, 2);
  Field r1 = random_field(n, 1, -10, 10, 3), r2 = random_field(n, 1, -1, 1, 4);
  Field a1(n / 2, 1), a2(n / 2, 1), b1(n / 2, 1), b2(n / 2, 1);
  nso_residual_restrict(phi, nu, r1, r2, kParams, a1, a2);
  nso_residual_restrict_ref(phi, nu, r1, r2, kParams, b1, b2);
  EXPECT_GT(testing::max_abs(a1), 1.0);
  // Values ~ 1e2 (ResidualMatchesReference); summation order only.
  EXPECT_LE(max_abs_diff(a1, b1), 1e-10);
  EXPECT_LE(max_abs_diff(a2, b2), 1e-12);
  // The same bits as the defect written and restricted (the paper-faithful V-cycle's).
  Field d1(n, 1), d2(n, 1), c1(n / 2, 1), c2(n / 2, 1);
  nso_residual(phi, nu, &r1, &r2, kParams, d1, d2);
  restrict_average(d1, c1);
  restrict_average(d2, c2);
  EXPECT_EQ(max_abs_diff(a1, c1), 0.0);
  EXPECT_EQ(max_abs_diff(a2, c2), 0.0);
}

TEST(CahnHilliard, SourceMatchesReference) {
  const int n = kTwinN;
  const double dt = 0.5 / n;
  const Field phi = random_field(n, 1, 0, 1, 30);
  Field a1 = random_field(n, 1, -1, 1, 31), a2 = a1, b1 = a1, b2 = a1;
  ch_source(phi, dt, a1, a2);
  ch_source_ref(phi, dt, b1, b2);
  // phi/dt ~ 64 and Lap phi / 4 ~ 1.5 n^2 / 4: values ~ 4e2, summation order only.
  EXPECT_LE(max_abs_diff(a1, b1), 1e-11);
  EXPECT_EQ(max_abs_diff(a2, b2), 0.0);
  EXPECT_EQ(testing::max_abs(a2), 0.0);
}

// The step's first pass against the source, the copy and the norm it replaces: the same bits
// (the step's V-cycle count and stop depend on this norm), at one and two threads, below
// kParallelMinN (serial there) and above it with an uneven slab split.
TEST(CahnHilliard, SourceFirstDefectMatchesSeparatePassesBitForBit) {
  const int saved_threads = omp_get_max_threads();
  for (const int threads : {1, 2}) {
    omp_set_num_threads(threads);
    for (const int n : {8, 16, kParallelMinN + 3}) {
      const ChParams p{0.02, 0.5 / n, SweepOrder::kRedBlack};
      // As in a step: phi^n with the measures' two ghost layers, the solver's fields with one.
      const Field phi = random_field(n, 2, 0, 1, 40), nu = random_field(n, 1, -0.1, 0.1, 41);
      Field a1 = random_field(n, 1, -1, 1, 42), a2 = a1, b1 = a1, b2 = a1;
      Field ga = random_field(n, 1, -1, 1, 43), gb = ga;
      const double fused = ch_source_first_defect(phi, nu, p, a1, a2, ga);
      const double ref = ch_source_first_defect_ref(phi, nu, p, b1, b2, gb);
      const std::string what = fmt::format("n {} threads {}", n, threads);
      EXPECT_GT(ref, 0.1) << what;
      EXPECT_EQ(fused, ref) << what;
      EXPECT_EQ(max_abs_diff(a1, b1), 0.0) << what;
      EXPECT_EQ(max_abs_diff(a2, b2), 0.0) << what;
      EXPECT_EQ(max_abs_diff(ga, phi), 0.0) << what;
    }
  }
  omp_set_num_threads(saved_threads);
}

// The same pass with its extras (the history's copies and phi_n's mean), against the separate
// passes and mean(): bit for bit at 1 and 2 threads, below and above kParallelMinN (mean runs
// serially below it) and on an odd size (uneven slabs).
TEST(CahnHilliard, SourceFirstDefectExtrasMatchSeparatePassesBitForBit) {
  const int saved_threads = omp_get_max_threads();
  for (const int threads : {1, 2}) {
    omp_set_num_threads(threads);
    for (const int n : {8, 16, kParallelMinN + 3}) {
      const ChParams p{0.02, 0.5 / n, SweepOrder::kRedBlack};
      const Field phi = random_field(n, 2, 0, 1, 50), nu = random_field(n, 1, -0.1, 0.1, 51);
      Field a1 = random_field(n, 1, -1, 1, 52), a2 = a1, b1 = a1, b2 = a1;
      Field ga = random_field(n, 1, -1, 1, 53), gb = ga;
      Field pa = random_field(n, 0, -1, 1, 54), pb = pa, qa = pa, qb = pa;
      double ma = -1.0, mb = -2.0;
      const double fused = ch_source_first_defect(phi, nu, p, a1, a2, ga, {&pa, &qa, &ma});
      const double ref = ch_source_first_defect_ref(phi, nu, p, b1, b2, gb, {&pb, &qb, &mb});
      const std::string what = fmt::format("n {} threads {}", n, threads);
      EXPECT_EQ(fused, ref) << what;
      EXPECT_EQ(fused, ch_source_first_defect(phi, nu, p, a1, a2, ga)) << what;  // no extras
      EXPECT_EQ(ma, mb) << what;
      EXPECT_EQ(ma, mean(phi)) << what;
      EXPECT_GT(ma, 0.4) << what;
      EXPECT_EQ(max_abs_diff(a1, b1), 0.0) << what;
      EXPECT_EQ(max_abs_diff(a2, b2), 0.0) << what;
      EXPECT_EQ(max_abs_diff(pa, phi), 0.0) << what;
      EXPECT_EQ(max_abs_diff(qa, nu), 0.0) << what;
      // Only the mean, as a step with its history in place asks.
      double mc = -3.0;
      StepStartExtras only_mean;
      only_mean.phi_mean = &mc;
      EXPECT_EQ(ch_source_first_defect(phi, nu, p, a1, a2, ga, only_mean), ref) << what;
      EXPECT_EQ(mc, mb) << what;
    }
  }
  omp_set_num_threads(saved_threads);
}

// The defect norm with the mean of phi in its pass, against nso_residual_norm and mean().
TEST(CahnHilliard, ResidualNormMeanMatchesSeparatePassesBitForBit) {
  const int saved_threads = omp_get_max_threads();
  for (const int threads : {1, 2}) {
    omp_set_num_threads(threads);
    for (const int n : {8, 16, kParallelMinN + 3}) {
      const ChParams p{0.02, 0.5 / n, SweepOrder::kRedBlack};
      Field phi = random_field(n, 1, 0, 1, 60), nu = random_field(n, 1, -0.1, 0.1, 61);
      const Field r1 = random_field(n, 1, -1, 1, 62), r2 = random_field(n, 1, -1, 1, 63);
      double ma = -1.0, mb = -2.0;
      const double fused = nso_residual_norm_mean(phi, nu, r1, r2, p, ma);
      const double ref = nso_residual_norm_mean_ref(phi, nu, r1, r2, p, mb);
      const std::string what = fmt::format("n {} threads {}", n, threads);
      EXPECT_GT(ref, 0.1) << what;
      EXPECT_EQ(fused, ref) << what;
      EXPECT_EQ(fused, nso_residual_norm(phi, nu, r1, r2, p)) << what;
      EXPECT_EQ(ma, mb) << what;
      EXPECT_GT(ma, 0.4) << what;
    }
  }
  omp_set_num_threads(saved_threads);
}

// The step's end: the copy with the mass shift added, then the exchange, against copy, exchange
// and add_constant over the padded field; a zero shift copies (-0.0 kept).
TEST(CahnHilliard, CopyInteriorPlusMatchesReferenceBitForBit) {
  for (const int n : {8, kParallelMinN + 3}) {
    Field src = random_field(n, 1, 0, 1, 70);
    src(1, 2, 3) = -0.0;
    for (const double c : {0.0, 3.1e-9, -0.25}) {
      Field a = random_field(n, 2, -1, 1, 71), b = a;
      copy_interior_plus(src, c, a);
      a.exchange_halo();
      copy_interior_plus_ref(src, c, b);
      const std::string what = fmt::format("n {} c {}", n, c);
      EXPECT_EQ(std::memcmp(a.data(), b.data(), sizeof(double) * a.storage_size()), 0) << what;
      if (c == 0.0) {
        EXPECT_TRUE(std::signbit(a(1, 2, 3))) << what;
      }
      EXPECT_EQ(a(4, 5, 6), src(4, 5, 6) + c) << what;
    }
  }
}

TEST(CahnHilliard, DefectNormMatchesReference) {
  const int n = kTwinN;
  const Field d1 = random_field(n, 1, -100, 100, 32), d2 = random_field(n, 1, -1, 1, 33);
  const double dt = 0.5 / n;
  const double a = ch_defect_norm(d1, d2, dt), b = ch_defect_norm_ref(d1, d2, dt);
  EXPECT_GT(a, 1.0);
  EXPECT_NEAR(a, b, 1e-13 * b);
  // Both components count, phi's in units of phi (times dt).
  const Field zero(n, 1);
  EXPECT_NEAR(ch_defect_norm(d1, zero, dt), dt * 100 / std::sqrt(3.0), 0.01 * dt * 100);
  EXPECT_NEAR(ch_defect_norm(zero, d2, dt), 1 / std::sqrt(3.0), 0.01);
  EXPECT_EQ(ChOperator(kParams).norm({d1, d2}), ch_defect_norm(d1, d2, kParams.dt));
}

// The extrapolated guess, also in place (guess = x, as the stepper does for nu).
TEST(CahnHilliard, ExtrapolationMatchesReference) {
  const int n = kTwinN;
  const Field x = random_field(n, 1, 0, 1, 34);
  const Field prev = random_field(n, 0, 0, 1, 35);
  Field prev1 = prev, prev2 = prev, g1(n, 1), g2(n, 1);
  extrapolate_into(x, prev1, g1, 0.75);
  extrapolate_into_ref(x, prev2, g2, 0.75);
  EXPECT_EQ(max_abs_diff(g1, g2), 0.0);
  EXPECT_EQ(max_abs_diff(prev1, x), 0.0);
  EXPECT_EQ(max_abs_diff(prev2, x), 0.0);
  EXPECT_NEAR(g1(3, 4, 5), x(3, 4, 5) + 0.75 * (x(3, 4, 5) - prev(3, 4, 5)), 1e-15);
  Field y1 = x, y2 = x;
  prev1 = prev;
  prev2 = prev;
  extrapolate_into(y1, prev1, y1, 2.0);
  extrapolate_into_ref(y2, prev2, y2, 2.0);
  EXPECT_EQ(max_abs_diff(y1, y2), 0.0);
  EXPECT_NEAR(y1(3, 4, 5), x(3, 4, 5) + 2.0 * (x(3, 4, 5) - prev(3, 4, 5)), 1e-15);
  EXPECT_EQ(max_abs_diff(prev1, x), 0.0);
}

TEST(CahnHilliard, RedBlackSmootherMatchesReference) {
  const int n = kTwinN;
  Field phi1 = random_field(n, 1, 0, 1, 5), nu1 = random_field(n, 1, -0.1, 0.1, 6);
  Field s1 = random_field(n, 1, -10, 10, 7), s2 = random_field(n, 1, -1, 1, 8);
  Field phi2 = phi1, nu2 = nu1;
  for (int colour = 0; colour < 2; ++colour) {
    smooth_color(phi1, nu1, s1, s2, kParams, colour);
    smooth_color_ref(phi2, nu2, s1, s2, kParams, colour);
    exchange_halos(phi1, nu1);
    exchange_halos(phi2, nu2);
  }
  EXPECT_LE(max_abs_diff(phi1, phi2), 1e-13);
  EXPECT_LE(max_abs_diff(nu1, nu2), 1e-13);
}

// The lexicographic sweep (its row kernel) against the cell-by-cell reference.
TEST(CahnHilliard, LexicographicSmootherMatchesReference) {
  const int n = kTwinN;
  Field phi1 = random_field(n, 1, 0, 1, 36), nu1 = random_field(n, 1, -0.1, 0.1, 37);
  Field s1 = random_field(n, 1, -10, 10, 38), s2 = random_field(n, 1, -1, 1, 39);
  Field phi2 = phi1, nu2 = nu1;
  for (int sweep = 0; sweep < 2; ++sweep) {
    smooth_lexicographic(phi1, nu1, s1, s2, kParams);
    smooth_lexicographic_ref(phi2, nu2, s1, s2, kParams);
    EXPECT_TRUE(halo_is_current(phi1) && halo_is_current(nu1));
  }
  EXPECT_GT(max_abs_diff(phi1, random_field(n, 1, 0, 1, 36)), 0.01);  // it did relax
  EXPECT_LE(max_abs_diff(phi1, phi2), 1e-13);
  EXPECT_LE(max_abs_diff(nu1, nu2), 1e-13);
}

// `sweeps` sweeps of the fused one-pass red-black smoother against the two-pass smoother
// (smooth_color, the same point solve, with a halo exchange after each colour) bit for bit, and
// against the reference colour passes (Cramer's rule written out) to round-off. Sizes: the
// V-cycle's coarse levels (2, 4, 6, 8, 16: one thread below kParallelMinN) and slabs that
// split unevenly (34, 36) at 1, 2 and 3 threads (the barrier-separated planes around the slab
// boundaries are where a wrong order would show); ghost widths 1 to 3. The fused sweep returns
// with valid ghosts: no exchange between calls.
TEST(CahnHilliard, RedBlackFusedSweepMatchesReference) {
  const int saved_threads = omp_get_max_threads();
  for (const int threads : {1, 2, 3}) {
    omp_set_num_threads(threads);
    for (const int n : {2, 4, 6, 8, 16, 34, 36}) {
      if (threads > 1 && n < kParallelMinN) continue;  // serial there
      for (const int ghost : {1, 2, 3}) {
        for (const int sweeps : {1, 2, 3}) {
          if (ghost > n || (sweeps > 1 && n < 4 * sweeps)) continue;
          const ChParams p{0.01, 0.5 / n, SweepOrder::kRedBlack};
          const Field phi0 = random_field(n, ghost, 0, 1, 5);
          const Field nu0 = random_field(n, ghost, -0.1, 0.1, 6);
          const Field s1 = random_field(n, 1, -10, 10, 7), s2 = random_field(n, 1, -1, 1, 8);
          Field phi1 = phi0, nu1 = nu0, phi2 = phi0, nu2 = nu0, phi3 = phi0, nu3 = nu0;
          const std::string what = fmt::format("n {} ghost {} sweeps {} threads {}", n, ghost,
                                               sweeps, threads);
          for (int call = 0; call < 2; ++call) {
            smooth_red_black_fused(phi1, nu1, s1, s2, p, sweeps);
            EXPECT_TRUE(halo_is_current(phi1) && halo_is_current(nu1)) << what;
            for (int stage = 0; stage < 2 * sweeps; ++stage) {
              smooth_color(phi2, nu2, s1, s2, p, stage % 2);
              exchange_halos(phi2, nu2);
              if (threads > 1) continue;  // the serial reference, once
              smooth_color_ref(phi3, nu3, s1, s2, p, stage % 2);
              exchange_halos(phi3, nu3);
            }
          }
          EXPECT_GT(max_abs_diff(phi1, phi0), 0.01) << what;
          EXPECT_EQ(max_abs_diff(phi1, phi2), 0.0) << what;
          EXPECT_EQ(max_abs_diff(nu1, nu2), 0.0) << what;
          if (threads > 1) continue;
          EXPECT_LE(max_abs_diff(phi1, phi3), 1e-13) << what;
          EXPECT_LE(max_abs_diff(nu1, nu3), 1e-13) << what;
        }
      }
    }
  }
  omp_set_num_threads(saved_threads);
}

// ChOperator::smooth pairs its sweeps into two-sweep passes where the grid allows: any count of
// sweeps gives the bits of as many single sweeps, on the sizes a V-cycle's levels take.
TEST(CahnHilliard, OperatorSmoothBlocksSweepsBitForBit) {
  for (const int n : {2, 4, 8, 16, 32}) {
    const ChOperator op({0.01, 0.5 / n, SweepOrder::kRedBlack});
    const Fields rhs{random_field(n, 1, -10, 10, 44), random_field(n, 1, -1, 1, 45)};
    for (const int sweeps : {1, 2, 3, 4, 5}) {
      Fields u{random_field(n, 1, 0, 1, 46), random_field(n, 1, -0.1, 0.1, 47)};
      Fields v = u;
      op.smooth(u, rhs, sweeps);
      for (int s = 0; s < sweeps; ++s)
        smooth_red_black_fused(v[0], v[1], rhs[0], rhs[1], op.params(), 1);
      EXPECT_EQ(max_abs_diff(u[0], v[0]), 0.0) << n << " sweeps " << sweeps;
      EXPECT_EQ(max_abs_diff(u[1], v[1]), 0.0) << n << " sweeps " << sweeps;
      EXPECT_TRUE(halo_is_current(u[0]) && halo_is_current(u[1])) << n;
    }
  }
}

// The operator follows the ghost rule: smooth() returns u with valid ghosts for both orderings
// and for the odd sizes that fall back to lexicographic; apply() and residual() take u const.
TEST(CahnHilliard, OperatorSmoothLeavesGhostsValid) {
  for (const SweepOrder order : {SweepOrder::kRedBlack, SweepOrder::kLexicographic}) {
    for (const int n : {6, 16, 48}) {
      const ChOperator op({0.01, 0.5 / n, order});
      Fields u{random_field(n, 1, 0, 1, 40), random_field(n, 1, -0.1, 0.1, 41)};
      const Fields rhs{random_field(n, 1, -10, 10, 42), random_field(n, 1, -1, 1, 43)};
      op.smooth(u, rhs, 2);
      EXPECT_TRUE(halo_is_current(u[0]) && halo_is_current(u[1])) << n;
      Fields a{Field(n, 1), Field(n, 1)}, b{Field(n, 1), Field(n, 1)};
      op.apply(u, a);
      op.residual(u, rhs, b);
      for (int c = 0; c < 2; ++c) {  // residual = rhs - apply
        double worst = 0.0;
        for_each_cell(a[c], [&](int i, int j, int k) {
          worst = std::max(worst, std::abs(a[c](i, j, k) + b[c](i, j, k) - rhs[c](i, j, k)));
        });
        EXPECT_LE(worst, 1e-10) << n << " component " << c;
      }
    }
  }
}

TEST(CahnHilliard, PointSolveSatisfiesLinearisedEquations) {
  // After relaxing a cell, (A.3) holds exactly at it and (A.4) with f linearised at the old
  // value; with all other cells frozen.
  const int n = 8;
  Field phi = random_field(n, 1, 0, 1, 9), nu = random_field(n, 1, -0.1, 0.1, 10);
  Field s1 = random_field(n, 1, -10, 10, 11), s2 = random_field(n, 1, -1, 1, 12);
  const double m = phi(2, 2, 2);
  smooth_color(phi, nu, s1, s2, kParams, 0);  // (2,2,2) is colour 0
  const double h2 = 1.0 / (n * n), e2 = kParams.epsilon * kParams.epsilon;
  auto nb = [&](const Field& f) {
    return f(3, 2, 2) + f(1, 2, 2) + f(2, 3, 2) + f(2, 1, 2) + f(2, 2, 3) + f(2, 2, 1);
  };
  const double p = phi(2, 2, 2), v = nu(2, 2, 2);
  const double f_lin = ch_f(m) + ch_df(m) * (p - m);
  EXPECT_NEAR(p / kParams.dt - (nb(nu) - 6 * v) / h2, s1(2, 2, 2), 1e-9);
  EXPECT_NEAR(-f_lin + e2 * (nb(phi) - 6 * p) / h2 + v, s2(2, 2, 2), 1e-12);
}

// Mean V-cycle reduction factor over `cycles` cycles of the first step from the gyroid.
double vcycle_factor(int n, int cycles) {
  Field phi = testing::gyroid_field(n, 1);
  ChParams p{0.01 * 64.0 / n, 0.5 / n, SweepOrder::kRedBlack};
  StepSolverOptions o;
  o.tol = 0.0;
  o.max_vcycles = cycles;
  ChStepper stepper(n, p, o);
  const StepStats s = stepper.step(phi);
  return std::pow(s.residual / s.first_residual, 1.0 / s.vcycles);
}

TEST(CahnHilliard, VCycleFactorIsIndependentOfN) {
  // epsilon scales with h so that the interface keeps its number of cells, as in Table 1.
  const double f16 = vcycle_factor(16, 5), f32 = vcycle_factor(32, 5), f64 = vcycle_factor(64, 5);
  RecordProperty("factor16", std::to_string(f16));
  RecordProperty("factor32", std::to_string(f32));
  RecordProperty("factor64", std::to_string(f64));
  std::printf("V-cycle reduction factors: 16^3 %.3f, 32^3 %.3f, 64^3 %.3f\n", f16, f32, f64);
  // Measured 0.018, 0.022, 0.024: h-independent to within the slow growth typical of
  // piecewise-constant interpolation; allow 3x margin on the factor and 2x on the spread.
  for (double f : {f16, f32, f64}) EXPECT_LT(f, 0.08);
  EXPECT_LT(std::max({f16, f32, f64}) / std::min({f16, f32, f64}), 2.0);
}

// The solver's own conservation, without the stepper's correction: the periodic Laplacians
// sum to zero, so mean(phi^{n+1}) - mean(phi^n) = -dt mean(d_phi) for the defect d_phi of
// Eq. (5) left by the V-cycles, and |dt mean(d_phi)| <= the defect norm. Each step's drift is
// therefore bounded by its final defect (plus round-off of the means, ~1e-16 each); a kernel
// reading stale ghosts or a Laplacian that does not telescope breaks the bound.
TEST(CahnHilliard, MassSolverConservesToItsDefect) {
  const int n = 32;
  Field phi = testing::gyroid_field(n, 1);
  StepSolverOptions o;
  o.tol = 1e-10;
  o.restore_mass = false;
  ChStepper stepper(n, {0.01, 0.5 / n, SweepOrder::kRedBlack}, o);
  const double m0 = mean(phi);
  double bound = 0.0;
  for (int s = 0; s < 20; ++s) {
    const double before = mean(phi);
    const StepStats st = stepper.step(phi);
    ASSERT_TRUE(st.converged);
    EXPECT_LE(std::abs(mean(phi) - before), st.residual + 1e-15) << "step " << s;
    bound += st.residual;
  }
  EXPECT_LE(std::abs(mean(phi) - m0), bound + 1e-14);
}

// The stepper's correction, separately: with a loose tolerance (1e-4) the solver alone drifts
// the mass by far more than round-off (measured 6.5e-11 over 10 steps at 32^3, against ~1e-16
// per step of round-off); restore_mass (the default) removes the drift to round-off (measured
// 5e-16).
TEST(CahnHilliard, MassRestoreRemovesTheDrift) {
  const int n = 32;
  auto drift = [n](bool restore) {
    Field phi = testing::gyroid_field(n, 1);
    const double m0 = mean(phi);
    StepSolverOptions o;
    o.tol = 1e-4;
    o.restore_mass = restore;
    ChStepper stepper(n, {0.01, 0.5 / n, SweepOrder::kRedBlack}, o);
    for (int s = 0; s < 10; ++s) stepper.step(phi);
    EXPECT_TRUE(halo_is_current(phi));
    return std::abs(mean(phi) - m0);
  };
  EXPECT_GT(drift(false), 1e-12);
  EXPECT_LE(drift(true), 1e-14);
}

// A rejected mix gets the step's field back from the stepper: the same bits as the step left,
// ghosts included, with and without extrapolation and a mass shift.
TEST(CahnHilliard, RewriteStepResultGivesTheStepsFieldBack) {
  const int n = 32;
  for (const bool extrapolate : {false, true}) {
    Field phi = testing::gyroid_field(n, 2);
    StepSolverOptions o;
    o.tol = 1e-5;  // loose: a mass shift to restore
    o.extrapolate = extrapolate;
    ChStepper stepper(n, {0.01, 0.5 / n, SweepOrder::kRedBlack}, o);
    for (int s = 0; s < 3; ++s) {
      stepper.step(phi);
      const Field after = phi;
      add_constant(phi, 0.125);  // as a mix would change it
      stepper.rewrite_step_result(phi);
      EXPECT_EQ(std::memcmp(phi.data(), after.data(), sizeof(double) * phi.storage_size()), 0)
          << "extrapolate " << extrapolate << " step " << s;
    }
    // After reset_nu the history restarts in the first pass: the next steps go on alike.
    Field other = phi;
    ChStepper twin(n, {0.01, 0.5 / n, SweepOrder::kRedBlack}, o);
    stepper.reset_nu();
    for (int s = 0; s < 3; ++s) {
      stepper.step(phi);
      twin.step(other);
    }
    EXPECT_EQ(max_abs_diff(phi, other), 0.0) << "extrapolate " << extrapolate;
  }
}

TEST(CahnHilliard, RedBlackAndLexicographicAgree) {
  const int n = 32;
  Field a = testing::gyroid_field(n, 1), b = a;
  StepSolverOptions o;
  o.tol = 1e-12;
  ChStepper rb(n, {0.01, 0.5 / n, SweepOrder::kRedBlack}, o);
  ChStepper lex(n, {0.01, 0.5 / n, SweepOrder::kLexicographic}, o);
  for (int s = 0; s < 3; ++s) {
    const StepStats sa = rb.step(a), sb = lex.step(b);
    EXPECT_TRUE(sa.converged);
    EXPECT_TRUE(sb.converged);
  }
  // Both solve the same discrete system to a defect of 1e-12; the solutions agree to a few
  // times that (the system's condition number at this dt is moderate).
  EXPECT_LE(max_abs_diff(a, b), 1e-10);
}

TEST(CahnHilliard, DivergenceIsReported) {
  const int n = 16;
  Field phi = random_field(n, 1, 0, 1, 20);
  phi(3, 3, 3) = std::nan("");
  phi.exchange_halo();
  ChStepper stepper(n, {0.01, 0.5 / n, SweepOrder::kRedBlack}, {});
  EXPECT_THROW(stepper.step(phi), SolverDiverged);
}

}  // namespace
}  // namespace cmcsurf
