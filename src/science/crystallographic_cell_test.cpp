#include "science/crystallographic_cell.h"

#include <gtest/gtest.h>

#include <cmath>

namespace cmcsurf {
namespace {

// The minimal surfaces' standard numbers per crystallographic cell (Hyde et al., The Language
// of Shape, Table 1.2): sigma P 2.3451, D 1.9189, G 3.0915; chi P -4, D -2, G -8; Gamma P
// 0.7163, D 0.7498, G 0.7667 to their 4 digits.
TEST(CrystallographicCell, DBoxHoldsEightPn3mCells) {
  const auto d = crystallographic_cell("D");
  ASSERT_TRUE(d);
  EXPECT_EQ(d->space_group, "Pn-3m");
  EXPECT_EQ(d->cells_per_computed_cell, 8);
  EXPECT_DOUBLE_EQ(d->lattice_ratio, 0.5);
  // The box holds 8 cells of edge 1/2: area 8 x 1.9189 / 4, chi -16.
  const CellNumbers c = per_crystallographic_cell(*d, 2 * 1.9189, -16, 1.0, -26.2);
  EXPECT_NEAR(c.area, 1.9189, 1e-12);
  EXPECT_DOUBLE_EQ(c.euler_characteristic, -2.0);
  EXPECT_DOUBLE_EQ(c.mean_curvature, 0.5);
  EXPECT_DOUBLE_EQ(c.mean_gaussian_curvature, -26.2 / 4);  // = 2 pi chi_c / sigma_c
  EXPECT_FALSE(crystallographic_cell("IWP"));
}

TEST(CrystallographicCell, HomogeneityIndexIsTheSameInEveryCell) {
  EXPECT_NEAR(homogeneity_index(2.3451, -4), 0.7163, 5e-5);
  EXPECT_NEAR(homogeneity_index(3.0915, -8), 0.7667, 5e-5);
  EXPECT_NEAR(homogeneity_index(1.9189, -2), 0.7498, 5e-5);
  // D in the box: 8 cells, sigma 8 x 1.9189 / 8^(2/3), chi -16.
  EXPECT_NEAR(homogeneity_index(2 * 1.9189, -16), homogeneity_index(1.9189, -2), 1e-12);
  EXPECT_TRUE(std::isnan(homogeneity_index(1.0, 0)));
}

}  // namespace
}  // namespace cmcsurf
