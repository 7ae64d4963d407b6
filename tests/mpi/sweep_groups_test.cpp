// Process groups for sweeps across nodes (Decomposition::split, gather_world_bytes), under
// mpirun -np 2 and -np 4 (CTest label mpi): every split of the world into equal groups, each
// group a decomposition of its own whose run equals the serial run.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "parallel/decomposition.h"
#include "pipeline/cmc.h"
#include "pipeline/sweep_groups.h"

namespace cmcsurf {
namespace {

std::shared_ptr<const Decomposition> world() { return Decomposition::world(); }

TEST(SweepGroups, SplitGivesEqualGroupsOfConsecutiveRanks) {
  const int ranks = world()->ranks();
  for (int groups = 1; groups <= ranks; ++groups) {
    if (ranks % groups != 0) continue;
    const int size = ranks / groups;
    const ProcessGroup g = Decomposition::split(groups);
    EXPECT_EQ(g.groups, groups);
    EXPECT_EQ(g.index, world()->rank() / size);
    const Decomposition& d = *g.decomposition;
    EXPECT_EQ(d.ranks(), size);
    EXPECT_EQ(d.rank(), world()->rank() % size);
    EXPECT_EQ(d.dims()[0] * d.dims()[1] * d.dims()[2], size);
    // Sums run over the group alone: its size, and the world ranks it holds.
    EXPECT_EQ(d.sum(1.0), double(size));
    const double first = g.index * size;
    EXPECT_EQ(d.sum(double(world()->rank())), size * first + size * (size - 1) / 2.0);
    // The grid checks without building a group agree with the group's own.
    for (int n : {8, 12, 16, 24, 20})
      EXPECT_EQ(Decomposition::check_grid_for(size, n), d.check_grid(n)) << n;
  }
  EXPECT_THROW(Decomposition::split(0), std::invalid_argument);
  EXPECT_THROW(Decomposition::split(ranks + 1), std::invalid_argument);
}

TEST(SweepGroups, WorldRankZeroGathersEveryonesBytes) {
  const int r = world()->rank();
  const std::string mine(std::size_t(r), char('a' + r));  // rank 0 sends nothing
  const std::vector<std::string> all = gather_world_bytes(mine);
  if (r == 0) {
    ASSERT_EQ(int(all.size()), world()->ranks());
    for (int k = 0; k < world()->ranks(); ++k)
      EXPECT_EQ(all[std::size_t(k)], std::string(std::size_t(k), char('a' + k)));
  } else {
    EXPECT_TRUE(all.empty());
  }
}

// Each group runs its own member at once, decomposed over its processes, as a sweep does: the
// same result as the serial run of that member (docs/scaling.md, to round-off).
TEST(SweepGroups, EachGroupRunsItsMemberAsTheSerialRun) {
  const int ranks = world()->ranks();
  const int groups = ranks >= 4 ? 2 : 1;  // groups of two processes
  const ProcessGroup g = Decomposition::split(groups);
  RunParams p;
  p.surface = g.index == 0 ? "P" : "D";
  p.volume_fraction = 0.4;
  p.grid = 16;
  p.max_steps = 12;
  p.tol = 1e-30;  // a fixed step count: no stop decision for round-off to flip
  p.constrain = Constraint::kMass;
  ASSERT_EQ(group_grid_problem(p, g.decomposition->ranks()), "");
  const RunResult serial = run_cmc(p);
  RunContext context;
  context.decomposition = g.decomposition;
  const RunResult split = run_cmc(p, context);
  EXPECT_EQ(split.history.size(), serial.history.size());
  EXPECT_EQ(split.vcycles, serial.vcycles);
  ASSERT_GT(serial.final.area, 0.5);  // a surface, not one phase
  const double rel = std::abs(split.final.area - serial.final.area) / serial.final.area;
  EXPECT_LE(rel, 1e-12) << "group " << g.index;
}

}  // namespace
}  // namespace cmcsurf
