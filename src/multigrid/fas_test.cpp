#include "multigrid/fas.h"

#include <gtest/gtest.h>

#include "../../tests/test_fields.h"
#include "multigrid/transfer.h"

namespace cmcsurf {
namespace {

// The transfer twins on a 64^3 -> 32^3 pair: the kernels' loops run in parallel from
// kParallelMinN fine cells per side (CTest runs them again with two threads).
TEST(Multigrid, RestrictionMatchesReference) {
  static_assert(64 >= kParallelMinN);
  Field fine = testing::random_field(64, 1, -1, 1, 11);
  Field a(32, 1), b(32, 1);
  restrict_average(fine, a);
  restrict_average_ref(fine, b);
  EXPECT_LE(testing::max_abs_diff(a, b), 1e-15);
}

TEST(Multigrid, RestrictionPreservesTheMean) {
  Field fine = testing::random_field(32, 1, -1, 1, 12);
  Field coarse(16, 1);
  restrict_average(fine, coarse);
  EXPECT_NEAR(testing::mean(coarse), testing::mean(fine), 1e-15);
}

TEST(Multigrid, InterpolatedCorrectionMatchesReference) {
  Field c = testing::random_field(32, 1, -1, 1, 13);
  Field c0 = testing::random_field(32, 1, -1, 1, 14);
  const Field before = testing::random_field(64, 1, -1, 1, 15);
  Field f1 = before, f2 = before;
  add_interpolated_correction(c, c0, f1);
  add_interpolated_correction_ref(c, c0, f2);
  EXPECT_EQ(testing::max_abs_diff(f1, f2), 0.0);
  // Piecewise constant: each of the 8 children of coarse cell (1, 2, 3) received that cell's
  // correction c - c0.
  const double correction = c(1, 2, 3) - c0(1, 2, 3);
  ASSERT_NE(correction, 0.0);
  for (int child = 0; child < 8; ++child) {
    const int i = 2 + (child & 1), j = 4 + (child >> 1 & 1), k = 6 + (child >> 2 & 1);
    EXPECT_NEAR(f1(i, j, k) - before(i, j, k), correction, 1e-15) << child;
  }
}

// Transfers refuse a pair that is not a coarsening (always-on check).
TEST(MultigridDeathTest, TransfersRefuseMismatchedLevels) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const Field fine = testing::random_field(16, 1, -1, 1, 16);
  Field wrong(4, 1);
  EXPECT_DEATH(restrict_average(fine, wrong), "check failed: is_coarsening");
}

TEST(Multigrid, CoarseningSizes) {
  EXPECT_EQ(coarsening_sizes(64), (std::vector<int>{64, 32, 16, 8, 4, 2}));
  EXPECT_EQ(coarsening_sizes(48), (std::vector<int>{48, 24, 12, 6, 3}));
  EXPECT_EQ(coarsening_sizes(12), (std::vector<int>{12, 6, 3}));
  EXPECT_TRUE(check_coarsenable(64).empty());
  EXPECT_TRUE(check_coarsenable(96).empty());
  EXPECT_TRUE(check_coarsenable(80).empty());
  EXPECT_FALSE(check_coarsenable(50).empty());   // 25 * 2
  EXPECT_FALSE(check_coarsenable(4).empty());    // too small
  EXPECT_FALSE(check_coarsenable(44).empty());   // 11 * 4
  EXPECT_NE(check_coarsenable(50).find("48 or 56"), std::string::npos);
  EXPECT_NE(check_coarsenable(5).find("(nearest accepted: 8)"), std::string::npos);
  // The ends of int (a Python grid=2**40 arrives clamped): no overflow, no long search.
  EXPECT_NE(check_coarsenable(2147483647).find("1879048192 or 2147483648"), std::string::npos);
  EXPECT_NE(check_coarsenable(-2147483647 - 1).find("(nearest accepted: 8)"), std::string::npos);
}

}  // namespace
}  // namespace cmcsurf
