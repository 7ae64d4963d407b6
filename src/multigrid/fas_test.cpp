#include "multigrid/fas.h"

#include <gtest/gtest.h>

#include "../../tests/test_fields.h"
#include "multigrid/transfer.h"

namespace cmcsurf {
namespace {

TEST(Multigrid, RestrictionMatchesReference) {
  Field fine = testing::random_field(16, 1, -1, 1, 11);
  Field a(8, 1), b(8, 1);
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
  Field c = testing::random_field(8, 1, -1, 1, 13);
  Field c0 = testing::random_field(8, 1, -1, 1, 14);
  Field f1 = testing::random_field(16, 1, -1, 1, 15);
  Field f2 = f1;
  add_interpolated_correction(c, c0, f1);
  add_interpolated_correction_ref(c, c0, f2);
  EXPECT_EQ(testing::max_abs_diff(f1, f2), 0.0);
  // Piecewise constant: the 8 children received the same correction.
  EXPECT_DOUBLE_EQ(f1(2, 4, 6) - f2(2, 4, 6), 0.0);
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
}

}  // namespace
}  // namespace cmcsurf
