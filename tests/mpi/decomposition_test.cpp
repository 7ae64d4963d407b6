// Domain decomposition against the serial code, run under mpirun -np 2 and -np 4 (CTest label
// mpi). Every process builds the serial (whole-grid) result itself and compares its block.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "../test_fields.h"
#include "cahn_hilliard/time_step.h"
#include "measure/measures.h"
#include "measure/sharp_volume.h"
#include "multigrid/fas.h"
#include "parallel/decomposition.h"
#include "pipeline/cmc.h"
#include "surfaces/initial.h"

namespace cmcsurf {
namespace {

std::shared_ptr<const Decomposition> world() { return Decomposition::world(); }

// This process's block of a whole field, halo exchanged through the decomposition.
Field block_of(const Field& whole) {
  Field b(whole.n(), whole.ghost(), world());
  take_block(whole, b);
  b.exchange_halo();
  return b;
}

// Largest |block - whole| over the block's interior (and ghosts when with_ghosts), over all
// processes.
double max_block_diff(const Field& block, const Field& whole, bool with_ghosts = false) {
  const int g = with_ghosts ? block.ghost() : 0;
  const auto& o = block.offset();
  double m = 0.0;
  for (int k = -g; k < block.nz() + g; ++k)
    for (int j = -g; j < block.ny() + g; ++j)
      for (int i = -g; i < block.nx() + g; ++i)
        m = std::max(m, std::abs(block(i, j, k) - whole(o[0] + i, o[1] + j, o[2] + k)));
  return world()->max(m);
}

TEST(Decomposition, RunsOnSeveralRanksWithAProcessGrid) {
  const auto d = world();
  EXPECT_GT(d->ranks(), 1);
  EXPECT_EQ(d->dims()[0] * d->dims()[1] * d->dims()[2], d->ranks());
  EXPECT_TRUE(d->splits(16));
  EXPECT_FALSE(d->splits(6));  // blocks of 3 or fewer cells
  EXPECT_DOUBLE_EQ(d->sum(1.0), double(d->ranks()));
  EXPECT_DOUBLE_EQ(d->max(double(d->rank())), double(d->ranks() - 1));
}

TEST(Decomposition, HaloExchangeEqualsTheSerialWrap) {
  for (int n : {16, 24})
    for (int g : {1, 2}) {
      const Field whole = testing::random_field(n, g, -1, 1, 7 + n + g);
      const Field block = block_of(whole);
      // Ghosts (edges and corners included) hold exactly the periodic images.
      EXPECT_EQ(max_block_diff(block, whole, true), 0.0) << "n " << n << " ghost " << g;
    }
}

TEST(Decomposition, PairedHaloExchangeEqualsTheSerialWrap) {
  const Field phi = testing::random_field(16, 1, -1, 1, 31);
  const Field nu = testing::random_field(16, 1, -1, 1, 32);
  Field a(16, 1, world()), b(16, 1, world());
  take_block(phi, a);
  take_block(nu, b);
  exchange_halos(a, b);  // one message per neighbour carries both fields
  EXPECT_EQ(max_block_diff(a, phi, true), 0.0);
  EXPECT_EQ(max_block_diff(b, nu, true), 0.0);
}

TEST(Decomposition, GatherRestoresTheWholeField) {
  const Field whole = testing::random_field(16, 2, -1, 1, 3);
  const Field block = block_of(whole);
  Field back(16, 2);
  gather_field(block, back, true);
  EXPECT_EQ(testing::max_abs_diff(back, whole), 0.0);
}

// Sums over blocks are added in another order than the serial sum: round-off only (32^3 terms;
// 1e-13 is about 500 ulps).
TEST(Decomposition, ReductionsMatchSerialToRoundOff) {
  Field whole = testing::gyroid_field(32, 2);
  Field block = block_of(whole);
  const double eps = 0.04;
  auto rel = [](double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); };
  EXPECT_LE(rel(mass(block), mass(whole)), 1e-13);
  EXPECT_LE(rel(area(block, eps), area(whole, eps)), 1e-13);
  EXPECT_LE(rel(energy(block, eps), energy(whole, eps)), 1e-13);
  EXPECT_LE(rel(sharp_volume_fraction(block), sharp_volume_fraction(whole)), 1e-13);
  EXPECT_EQ(volume_fraction(block), volume_fraction(whole));  // integer counts
  Field shifted = whole;
  add_constant(shifted, 0.1);
  EXPECT_LE(rel(l2_diff(block_of(shifted), block), l2_diff(shifted, whole)), 1e-13);
  EXPECT_LE(rel(average_volume_fraction(block, 0.3, 0.6),
                average_volume_fraction(whole, 0.3, 0.6)), 1e-13);
  // The balanced gyroid has H = 0: curvature on a sphere (H = 1/r), its block built in place.
  InitialFieldParams sphere;
  sphere.surface = "sphere";
  sphere.epsilon = eps;
  sphere.radius = 0.3;
  Field ball = make_initial_field(sphere, 32, 2);
  Field ball_block = make_initial_field(sphere, 32, 2, world());
  EXPECT_EQ(max_block_diff(ball_block, ball, true), 0.0);
  EXPECT_LE(rel(mean_curvature(ball_block), mean_curvature(ball)), 1e-12);
  EXPECT_LE(rel(mean_curvature_mu(ball_block, eps), mean_curvature_mu(ball, eps)), 1e-12);
}

// One FAS V-cycle (red-black smoothing, transfers, gathered coarse levels) on the blocks
// against the same cycle on the whole grid.
TEST(Decomposition, VCycleMatchesSerial) {
  const int n = 16;
  const ChParams params{0.05, 0.5 / n, SweepOrder::kRedBlack};
  const ChOperator op(params);
  FasOptions fas;
  FasSolver serial(n, 2, 1, fas);
  FasSolver split(n, 2, 1, fas, world());
  ASSERT_EQ(serial.levels(), split.levels());
  EXPECT_TRUE(split.distributed(0));
  EXPECT_FALSE(split.distributed(split.levels() - 1));
  Field phi = testing::gyroid_field(n, 1);
  Field nu = testing::random_field(n, 1, -0.1, 0.1, 21);
  ch_source(phi, params.dt, serial.rhs()[0], serial.rhs()[1]);
  copy_interior(phi, serial.solution()[0]);
  copy_interior(nu, serial.solution()[1]);
  for (int c = 0; c < 2; ++c) {
    take_block(serial.rhs()[c], split.rhs()[c]);
    take_block(serial.solution()[c], split.solution()[c]);
  }
  const double r0 = serial.residual_norm(op);
  EXPECT_LE(std::abs(split.residual_norm(op) - r0), 1e-13 * r0);
  for (int cycle = 1; cycle <= 3; ++cycle) {
    serial.vcycle(op);
    split.vcycle(op);
    for (int c = 0; c < 2; ++c) {
      const double scale = l2_norm(serial.solution()[c]);
      const double diff = max_block_diff(split.solution()[c], serial.solution()[c]);
      EXPECT_LE(diff, 1e-12 * scale) << "cycle " << cycle << " component " << c;
      if (world()->rank() == 0)
        std::printf("V-cycle %d, component %d: max |split - serial| = %.2e (scale %.2e)\n",
                    cycle, c, diff, scale);
    }
  }
  const double r = serial.residual_norm(op);
  EXPECT_LT(r, 0.1 * r0);  // the cycle converges
  EXPECT_LE(std::abs(split.residual_norm(op) - r), 1e-9 * r);
}

// A few steps of the whole CMC algorithm (pre-relaxation, bisection, threshold, shift, relax).
TEST(Decomposition, ShortRunMatchesSerial) {
  RunParams p;
  p.surface = "G";
  p.volume_fraction = 0.3;
  // A grid and epsilon that keep the gyroid (at 16^3 with epsilon 0.05 the field ended in
  // one phase, so the area compared 0 with 0).
  p.grid = 32;
  p.epsilon = 0.03;
  p.max_steps = 6;
  p.prerelax_steps = 2;
  p.constrain = Constraint::kMass;
  const RunResult serial = run_cmc(p);
  RunContext context;
  context.decomposition = world();
  const RunResult split = run_cmc(p, context);
  ASSERT_GT(serial.final.area, 2.0);  // a surface to compare (G at 0.3: about 2.9)
  ASSERT_EQ(split.history.size(), serial.history.size());
  EXPECT_EQ(split.vcycles, serial.vcycles);
  EXPECT_EQ(split.bisection->iterations, serial.bisection->iterations);
  EXPECT_EQ(split.bisection->beta, serial.bisection->beta);
  auto rel = [](double a, double b) { return a == b ? 0.0 : std::abs(a - b) / std::abs(b); };
  EXPECT_LE(rel(split.final.area, serial.final.area), 1e-12);  // sharp, reduced over blocks
  EXPECT_LE(rel(split.final.mean_curvature, serial.final.mean_curvature), 1e-10);
  EXPECT_LE(rel(split.final.area_diffuse, serial.final.area_diffuse), 1e-12);
  EXPECT_LE(rel(split.final.volume_fraction, serial.final.volume_fraction), 1e-12);
  EXPECT_LE(rel(split.final.mass, serial.final.mass), 1e-13);
  EXPECT_LE(rel(split.final.energy, serial.final.energy), 1e-12);
  const double dphi = max_block_diff(split.phi, serial.phi);
  EXPECT_LE(dphi, 1e-12);
  if (world()->rank() == 0)
    std::printf("short run: area rel %.2e, volume fraction rel %.2e, max |dphi| %.2e\n",
                rel(split.final.area, serial.final.area),
                rel(split.final.volume_fraction, serial.final.volume_fraction), dphi);
}

}  // namespace
}  // namespace cmcsurf

int main(int argc, char** argv) {
  cmcsurf::ParallelSession session(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  const auto world = cmcsurf::Decomposition::world();
  if (world->rank() != 0) {  // one report, from rank 0
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  const int failed = RUN_ALL_TESTS();
  return int(world->max(double(failed)));
}
