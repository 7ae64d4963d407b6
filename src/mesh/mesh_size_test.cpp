#include "mesh/mesh_size.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace cmcsurf {
namespace {

// A voxel size gives the smallest accepted grid at or below it: 2 mm cells at 0.0625 mm are
// 32 exactly, at 0.05 mm 40 (5 * 8), at 0.045 mm 48 (45 is 5 * 9, not accepted), and a cell
// coarser than the voxel still gets the smallest grid, 8.
TEST(MeshSize, ResolutionPicksTheSmallestAcceptedGrid) {
  EXPECT_EQ(grid_for_resolution(2.0, 0.0625, 1024), 32);
  EXPECT_EQ(grid_for_resolution(2.0, 0.05, 1024), 40);
  EXPECT_EQ(grid_for_resolution(2.0, 0.045, 1024), 48);
  EXPECT_EQ(grid_for_resolution(2.0, 1.0, 1024), 8);
  EXPECT_LE(2.0 / grid_for_resolution(2.0, 0.033, 1024), 0.033);
  EXPECT_THROW(grid_for_resolution(2.0, 0.001, 1024), std::invalid_argument);
}

TEST(MeshSize, UnitsInMillimetres) {
  EXPECT_EQ(mesh_unit_mm("mm"), 1.0);
  EXPECT_EQ(mesh_unit_mm("um"), 1e-3);
  EXPECT_EQ(mesh_unit_mm("in"), 25.4);
  EXPECT_THROW(mesh_unit_mm("ft"), std::invalid_argument);
}

}  // namespace
}  // namespace cmcsurf
