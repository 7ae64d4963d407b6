#include "grid/field.h"

#include <gtest/gtest.h>

#include <cmath>

#include "../../tests/test_fields.h"

namespace cmcsurf {
namespace {

// Every ghost value equals the interior value at the periodic image.
void expect_periodic_halo(const Field& f) {
  const int n = f.n(), g = f.ghost();
  auto wrap = [n](int i) { return ((i % n) + n) % n; };
  for (int k = -g; k < n + g; ++k)
    for (int j = -g; j < n + g; ++j)
      for (int i = -g; i < n + g; ++i)
        ASSERT_EQ(f(i, j, k), f(wrap(i), wrap(j), wrap(k))) << i << " " << j << " " << k;
}

TEST(Grid, HaloIsPeriodicWrapWithOneGhost) {
  Field f = testing::random_field(8, 1, -1, 1, 3);
  expect_periodic_halo(f);
}

TEST(Grid, HaloIsPeriodicWrapWithTwoGhostsAndSmallN) {
  expect_periodic_halo(testing::random_field(6, 2, -1, 1, 4));
  expect_periodic_halo(testing::random_field(2, 2, -1, 1, 5));  // ghost as wide as the grid
  // Rows of four (y and z faces of 2^3 with one ghost) take the short-run loop, as x faces do.
  expect_periodic_halo(testing::random_field(2, 1, -1, 1, 8));
}

TEST(Grid, PlanHasSixSlabsInAxisOrder) {
  const auto plan = make_periodic_halo_plan(16, 2);
  ASSERT_EQ(plan->slabs.size(), 6u);
  for (int s = 0; s < 6; ++s) EXPECT_EQ(plan->slabs[s].axis, s / 2);
}

TEST(Grid, CopyInteriorBetweenGhostWidths) {
  Field a = testing::random_field(8, 1, 0, 1, 6);
  Field b(8, 2);
  copy_interior(a, b);
  EXPECT_EQ(testing::max_abs_diff(a, b), 0.0);
}

// The checker of the ghost rule can fail: a changed interior cell next to the wrap, or a
// changed ghost, makes the halo stale; an exchange makes it current again. NaN compares bit for
// bit (a NaN copied into its ghosts is current).
TEST(Grid, HaloIsCurrentDetectsStaleGhosts) {
  for (const int ghost : {1, 2}) {
    Field f = testing::random_field(8, ghost, -1, 1, 7);
    EXPECT_TRUE(halo_is_current(f));
    f(7, 3, 4) += 1.0;  // its image is the ghost at i = -1
    EXPECT_FALSE(halo_is_current(f)) << ghost;
    f.exchange_halo();
    EXPECT_TRUE(halo_is_current(f));
    f(3, 3, 3) += 1.0;  // an interior cell with no ghost image: still current
    EXPECT_TRUE(halo_is_current(f));
    f(-ghost, 8 + ghost - 1, -1) = 5.0;  // a corner ghost
    EXPECT_FALSE(halo_is_current(f)) << ghost;
    f.exchange_halo();
    f(0, 0, 7) = std::nan("");
    f.exchange_halo();
    EXPECT_TRUE(halo_is_current(f));
  }
  EXPECT_TRUE(halo_is_current(Field(8, 0)));
}

// The rule's other half: functions that change a field keep valid ghosts valid.
TEST(Grid, AddConstantAndFillKeepTheHaloCurrent) {
  Field f = testing::random_field(32, 2, -1, 1, 8);
  add_constant(f, 0.375);
  EXPECT_TRUE(halo_is_current(f));
  f.fill(2.0);
  EXPECT_TRUE(halo_is_current(f));
}

// mean() against a plain sum, at sizes whose loops run in parallel. The plain recursive sum of
// N = 48^3 values near 1 carries round-off of about sqrt(N) eps = 4e-14 (measured 1.4e-14;
// bound N eps = 1.2e-11).
TEST(Grid, MeanMatchesReference) {
  for (const int n : {8, kParallelMinN, 48}) {
    const Field f = testing::random_field(n, 1, -1, 3, 9);
    double sum = 0.0;
    for_each_cell(f, [&](int i, int j, int k) { sum += f(i, j, k); });
    EXPECT_NEAR(mean(f), sum / f.global_cells(), 1e-12) << n;
  }
}

#ifdef CMCSURF_CHECKED
// In checked builds a DCHECK on a stale halo, and an index outside the ghost layers, abort.
TEST(GridDeathTest, ChecksFireInCheckedBuilds) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  Field f = testing::random_field(8, 1, -1, 1, 10);
  f(0, 0, 0) = 9.0;
  EXPECT_DEATH(CMCSURF_DCHECK(halo_is_current(f)), "check failed: halo_is_current");
  EXPECT_DEATH((void)f(9, 0, 0), "check failed: in_storage");
}
#endif

TEST(Grid, StorageIsCacheLineAligned) {
  Field f(12, 1);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(f.data()) % 64, 0u);
}

}  // namespace
}  // namespace cmcsurf
