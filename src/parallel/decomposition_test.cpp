#include "parallel/decomposition.h"

#include <gtest/gtest.h>

#include "grid/field.h"

namespace cmcsurf {
namespace {

// Without mpirun (or without MPI) a run is one process holding the whole grid.
TEST(Decomposition, OneProcessOwnsTheWholeGrid) {
  const auto d = Decomposition::world();
  EXPECT_EQ(d->ranks(), 1);
  EXPECT_FALSE(d->distributed());
  EXPECT_EQ(d->dims(), (std::array<int, 3>{1, 1, 1}));
  const Block b = d->block(24);
  EXPECT_EQ(b.size, (std::array<int, 3>{24, 24, 24}));
  EXPECT_EQ(b.offset, (std::array<int, 3>{0, 0, 0}));
  EXPECT_DOUBLE_EQ(d->sum(2.5), 2.5);
  EXPECT_DOUBLE_EQ(d->max(-1.0), -1.0);
  EXPECT_EQ(d->max_exit_code(2), 2);
}

TEST(Decomposition, GridChecksNameTheProblem) {
  const auto d = Decomposition::self();
  EXPECT_TRUE(d->check_grid(8).empty());
  EXPECT_TRUE(d->check_grid(6).empty());
  EXPECT_FALSE(d->check_grid(5).empty());  // odd
  EXPECT_FALSE(d->check_grid(2).empty());  // below 4 cells per axis
  EXPECT_NE(d->check_grid(2).find("N = 2"), std::string::npos);
}

TEST(Decomposition, FieldOfASingleProcessIsWhole) {
  Field f(16, 2, Decomposition::world());
  EXPECT_TRUE(f.whole());
  EXPECT_EQ(f.decomposition(), nullptr);
  EXPECT_EQ(f.offset_parity(), 0);
  EXPECT_EQ(f.interior_size(), 16u * 16u * 16u);
  EXPECT_DOUBLE_EQ(f.global_cells(), 4096.0);
  EXPECT_DOUBLE_EQ(f.sum_over_ranks(3.0), 3.0);
}

}  // namespace
}  // namespace cmcsurf
