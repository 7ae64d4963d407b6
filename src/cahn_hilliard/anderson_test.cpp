#include "cahn_hilliard/anderson.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>

#include "../../tests/test_fields.h"

namespace cmcsurf {
namespace {

using testing::max_abs_diff;
using testing::random_field;

// Sizes >= kParallelMinN, where the mixer's loops run in parallel (CTest runs the *Reference*
// tests again with two threads).
constexpr int kN = 32;
static_assert(kN >= kParallelMinN);

// A linear contraction towards `fixed` with a rate per cell from `rates`: three rates (0.6,
// 0.8, 0.95, by cell) stand for the fast profile and the slow geometric modes of a time step.
// It keeps the mean of x - fixed when that mean is zero in each rate class; the test fields
// only need it to be a fixed map.
void apply_map(const Field& fixed, const Field& x, Field& g) {
  for_each_cell(x, [&](int i, int j, int k) {
    const double rate = (i + 2 * j + 3 * k) % 3 == 0 ? 0.6 : (i + j) % 2 == 0 ? 0.8 : 0.95;
    g(i, j, k) = fixed(i, j, k) + rate * (x(i, j, k) - fixed(i, j, k));
  });
}

// A contraction with 17 rates from 0.5 to 0.95: more than the mixer's depth can resolve, so
// its least-squares problems stay well conditioned (with three rates they become singular once
// solved, and the order of the sums then shows in the mixed fields).
void apply_spread_map(const Field& fixed, const Field& x, Field& g) {
  for_each_cell(x, [&](int i, int j, int k) {
    const double rate = 0.5 + 0.45 * ((7 * i + 13 * j + 5 * k) % 17) / 16.0;
    g(i, j, k) = fixed(i, j, k) + rate * (x(i, j, k) - fixed(i, j, k));
  });
}

TEST(Anderson, MixerMatchesReference) {
  const Field fixed = random_field(kN, 1, 0, 1, 1);
  Field x = random_field(kN, 1, 0, 1, 2), y = x, gx(kN, 1), gy(kN, 1);
  AndersonMixer mixer(3);
  AndersonMixerRef ref(3);
  int used = 0;
  for (int step = 0; step < 8; ++step) {
    apply_spread_map(fixed, x, gx);
    apply_spread_map(fixed, y, gy);
    const int a = mixer.mix(x, gx), b = ref.mix(y, gy);
    EXPECT_EQ(a, b) << step;
    used = std::max(used, a);
    // Fed the same fields, both store the same float differences and their Gram sums differ
    // in order only (1e-16 relative), which the normal equations (condition number ~1e4-1e5
    // here) make ~1e-11 in the fields. (Each goes on from the mixer's field: on diverging
    // paths a 1e-16 difference can round a stored difference to the next float, 6e-8 of it.)
    EXPECT_LE(max_abs_diff(gx, gy), 1e-10) << step;
    std::swap(x, gx);
    copy_interior(x, y);
  }
  EXPECT_EQ(used, 3);  // the ring filled and wrapped
}

// The mixer's passes are instantiated per column count (1 to 8) and run serially below
// kParallelMinN: every depth, on a grid below it (odd, so rows do not split evenly into SIMD
// lanes) and on one above, against the twin within the tolerance of MixerMatchesReference, on
// one thread, where the mixer adds its sums in the twin's order. (On two threads they add in
// another order, which the normal equations of 4 or more columns of this map amplify past
// 1e-10: 2.7e-10 at 4 columns, 3e-6 at 7, measured; MixerMatchesReference runs on two.)
TEST(Anderson, EveryDepthMatchesTheTwinInAndAboveTheSerialSizes) {
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  for (const int n : {kParallelMinN - 9, kN})
    for (int depth = 1; depth <= 8; ++depth) {
      const Field fixed = random_field(n, 1, 0, 1, 1);
      Field x = random_field(n, 1, 0, 1, 2), y = x, gx(n, 1), gy(n, 1);
      AndersonMixer mixer(depth);
      AndersonMixerRef ref(depth);
      int used = 0;
      for (int step = 0; step <= depth; ++step) {
        apply_spread_map(fixed, x, gx);
        apply_spread_map(fixed, y, gy);
        const int a = mixer.mix(x, gx), b = ref.mix(y, gy);
        ASSERT_EQ(a, b) << "n " << n << " depth " << depth << " step " << step;
        used = std::max(used, a);
        EXPECT_LE(max_abs_diff(gx, gy), 1e-10) << "n " << n << " depth " << depth;
        std::swap(x, gx);
        copy_interior(x, y);
      }
      EXPECT_EQ(used, depth) << "n " << n;  // every column count ran
    }
  omp_set_num_threads(saved);
}

TEST(Anderson, AcceleratesSlowModes) {
  const Field fixed = random_field(kN, 1, 0, 1, 3);
  const Field start = random_field(kN, 1, 0, 1, 4);
  const double e0 = max_abs_diff(start, fixed);
  Field plain = start, mixed = start, g(kN, 1);
  AndersonMixer mixer(4);
  constexpr int kSteps = 10;
  for (int step = 0; step < kSteps; ++step) {
    apply_map(fixed, plain, g);
    std::swap(plain, g);
    apply_map(fixed, mixed, g);
    mixer.mix(mixed, g);
    std::swap(mixed, g);
  }
  // Plain steps leave 0.95^10 = 0.60 of the slowest error; Anderson of depth >= 3 solves a
  // map with three rates exactly after four columns (as GMRES would), up to the float storage
  // of the differences (6e-8 of each) and the regularisation.
  EXPECT_GT(max_abs_diff(plain, fixed), 0.5 * e0);
  EXPECT_LT(max_abs_diff(mixed, fixed), 1e-5 * e0);
}

TEST(Anderson, MixingKeepsTheMean) {
  // A map that keeps the mean (a contraction towards the mean plus a mean-free pattern): the
  // mixed field is an affine combination of its values, so it keeps the mean too.
  const Field pattern = random_field(kN, 1, -1, 1, 5);
  const double shift = mean(pattern);
  Field x = random_field(kN, 1, 0, 1, 6), g(kN, 1);
  const double m0 = mean(x);
  AndersonMixer mixer(3);
  for (int step = 0; step < 6; ++step) {
    const double m = mean(x);
    for_each_cell(x, [&](int i, int j, int k) {
      const double rate = (i + j + k) % 2 == 0 ? 0.5 : 0.9;
      g(i, j, k) = rate * (x(i, j, k) - m) + 0.1 * (pattern(i, j, k) - shift);
    });
    add_constant(g, m - mean(g));  // the map keeps the mean
    mixer.mix(x, g);
    std::swap(x, g);
  }
  // The float rounding of the stored differences (6e-8 of each, <= 1 here) would move the
  // mean by ~1e-10; the mixer takes its mean out, leaving double round-off.
  EXPECT_NEAR(mean(x), m0, 1e-14);
}

TEST(Anderson, RestartsWhenTheResidualGrows) {
  const Field fixed = random_field(kN, 1, 0, 1, 7);
  Field x = random_field(kN, 1, 0, 1, 8), g(kN, 1);
  AndersonMixer mixer(3);
  apply_map(fixed, x, g);
  EXPECT_EQ(mixer.mix(x, g), 0);  // no history yet
  std::swap(x, g);
  apply_map(fixed, x, g);
  EXPECT_EQ(mixer.mix(x, g), 1);
  std::swap(x, g);
  // A different map (another fixed point far away): the residual jumps, the history goes.
  const Field other = random_field(kN, 1, 5, 6, 9);
  apply_map(other, x, g);
  const Field before = g;
  EXPECT_EQ(mixer.mix(x, g), 0);
  EXPECT_EQ(max_abs_diff(g, before), 0.0);
  std::swap(x, g);
  apply_map(other, x, g);
  EXPECT_EQ(mixer.mix(x, g), 1);  // it starts again from the jump
}

// The state a checkpoint carries: taken after the ring wrapped, with the slots outside the
// columns dropped (a checkpoint keeps only the columns), restored into a new mixer, it mixes the
// next steps to the same bits as the mixer it came from; a fresh mixer does not.
TEST(Anderson, StateTakenAndRestoredMixesTheSameBits) {
  const Field fixed = random_field(kN, 1, 0, 1, 10);
  Field x = random_field(kN, 1, 0, 1, 11), g(kN, 1);
  AndersonMixer mixer(3);
  for (int step = 0; step < 6; ++step) {
    apply_spread_map(fixed, x, g);
    mixer.mix(x, g);
    std::swap(x, g);
  }
  AndersonState state = mixer.take_state();
  ASSERT_EQ(state.columns, 3);
  ASSERT_TRUE(state.have_prev);
  const std::size_t cells = x.interior_size();
  EXPECT_EQ(state.problem(cells), "");
  AndersonState copy = state;
  mixer.restore_state(std::move(state));
  for (int s = 0; s < copy.depth; ++s) {
    copy.dg[std::size_t(s)].clear();
    copy.df[std::size_t(s)].clear();
  }
  EXPECT_NE(copy.problem(cells), "");  // the columns' arrays are missing
  const AndersonState full = mixer.take_state();
  for (const int s : copy.column_slots()) {
    copy.dg[std::size_t(s)] = full.dg[std::size_t(s)];
    copy.df[std::size_t(s)] = full.df[std::size_t(s)];
  }
  mixer.restore_state(AndersonState(full));
  EXPECT_EQ(copy.problem(cells), "");
  AndersonMixer resumed(3), fresh(3);
  resumed.restore_state(std::move(copy));
  Field y = x, z = x, gy(kN, 1), gz(kN, 1);
  int fresh_differs = 0;
  for (int step = 0; step < 5; ++step) {
    apply_spread_map(fixed, x, g);
    apply_spread_map(fixed, y, gy);
    apply_spread_map(fixed, z, gz);
    const int a = mixer.mix(x, g);
    EXPECT_EQ(resumed.mix(y, gy), a) << step;
    fresh.mix(z, gz);
    EXPECT_EQ(max_abs_diff(g, gy), 0.0) << step;
    EXPECT_EQ(resumed.last_residual(), mixer.last_residual()) << step;
    fresh_differs += max_abs_diff(g, gz) > 0.0;
    std::swap(x, g);
    std::swap(y, gy);
    std::swap(z, gz);
  }
  EXPECT_GT(fresh_differs, 0);  // the history matters: without it the mixing differs

  // Counts no mixer holds are named.
  AndersonState bad = full;
  bad.columns = 4;
  EXPECT_NE(bad.count_problem().find("4 column(s)"), std::string::npos);
  bad = full;
  bad.gram[0] = std::nan("");
  EXPECT_NE(bad.count_problem().find("non-finite"), std::string::npos);
  bad = full;
  bad.depth = 9;
  EXPECT_NE(bad.count_problem().find("depth 9"), std::string::npos);
}

}  // namespace
}  // namespace cmcsurf
