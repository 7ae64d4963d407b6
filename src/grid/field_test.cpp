#include "grid/field.h"

#include <gtest/gtest.h>

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

TEST(Grid, StorageIsCacheLineAligned) {
  Field f(12, 1);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(f.data()) % 64, 0u);
}

}  // namespace
}  // namespace cmcsurf
