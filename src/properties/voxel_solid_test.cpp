#include "properties/voxel_solid.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "measure/sharp_volume.h"
#include "surfaces/nodal_level.h"

namespace cmcsurf {
namespace {

// Two planar interfaces at z = 1/4 and 3/4 (cell faces for N divisible by 4), phase 1 between.
Field slab(int n, double width = 0.05) {
  Field phi(n, 2);
  for_each_cell(n, [&](int i, int j, int k) {
    const double z = (k + 0.5) / n;
    phi(i, j, k) = 0.5 + 0.5 * std::tanh((0.25 - std::abs(z - 0.5)) / width);
  });
  phi.exchange_halo();
  return phi;
}

// The nodal gyroid at volume fraction 0.3 with the equilibrium profile (a relaxed field's shape).
Field gyroid_tanh(int n) {
  Field phi = nodal_tanh_profile(nodal_level_set("G", 0.3, n), 1.5 / n);
  phi.exchange_halo();
  return phi;
}

TEST(DualCellFractions, MatchTheirReferenceAndAddUpToTheLinearVolume) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Field phi(12, 2);
  for_each_cell(phi, [&](int i, int j, int k) { phi(i, j, k) = u(rng); });
  phi.exchange_halo();
  Field a(12, 1), b(12, 1);
  dual_cell_fractions(phi, 0.5, a);
  dual_cell_fractions_ref(phi, 0.5, b);
  for_each_cell(a, [&](int i, int j, int k) { EXPECT_NEAR(a(i, j, k), b(i, j, k), 1e-15); });
  EXPECT_NEAR(mean(a), linear_volume_fraction(phi), 1e-14);
}

TEST(VoxelSolid, NetworkMeanIsTheSharpVolumeFractionAndPhaseTwoItsComplement) {
  const Field phi = gyroid_tanh(24);
  const VoxelSolid one = cmc_voxel_solid(phi, {});
  EXPECT_NEAR(one.solid_fraction, sharp_volume_fraction(phi), 1e-13);
  EXPECT_NEAR(one.porosity, 1.0 - one.solid_fraction, 1e-15);
  SolidSpec two;
  two.other_phase = true;
  const VoxelSolid other = cmc_voxel_solid(phi, two);
  EXPECT_NEAR(other.solid_fraction, 1.0 - one.solid_fraction, 1e-13);
  for_each_cell(one.fraction, [&](int i, int j, int k) {
    ASSERT_GE(one.fraction(i, j, k), 0.0);
    ASSERT_LE(one.fraction(i, j, k), 1.0);
    ASSERT_NEAR(one.fraction(i, j, k) + other.fraction(i, j, k), 1.0, 1e-14);
  });
}

TEST(VoxelSolid, SheetAroundPlanesHoldsExactlyItsThickness) {
  // Walls of thickness T around the two planes: solid fraction 2T, exact (the distance is
  // linear on each side and the walls' boundaries lie away from the planes' kink).
  const Field phi = slab(32);
  for (double t : {0.0625, 0.1, 0.15}) {
    SolidSpec s;
    s.kind = SolidKind::kSheet;
    s.thickness = t;
    const VoxelSolid v = cmc_voxel_solid(phi, s);
    EXPECT_NEAR(v.solid_fraction, 2.0 * t, 1e-12) << t;
    EXPECT_DOUBLE_EQ(v.thickness, t);
  }
}

TEST(VoxelSolid, SheetThicknessIsSolvedForThePorosity) {
  const Field phi = gyroid_tanh(24);
  SolidSpec s;
  s.kind = SolidKind::kSheet;
  s.porosity = 0.7;
  const VoxelSolid v = cmc_voxel_solid(phi, s);
  EXPECT_NEAR(v.porosity, 0.7, 1e-6);
  EXPECT_GT(v.thickness, 0.0);
  EXPECT_LT(v.thickness, 0.5);
  s.porosity = NAN;
  s.thickness = 0.9;
  EXPECT_THROW(cmc_voxel_solid(phi, s), std::invalid_argument);
}

TEST(VoxelSolid, NodalSolidsAreBuiltAtThePorosityAsked) {
  SolidSpec network;
  const VoxelSolid n = nodal_voxel_solid("G", 24, network, 0.7);
  EXPECT_NEAR(n.porosity, 0.7, 1e-6);
  SolidSpec sheet;
  sheet.kind = SolidKind::kSheet;
  const VoxelSolid band = nodal_voxel_solid("G", 24, sheet, 0.7, NodalSheet::kBand);
  EXPECT_NEAR(band.porosity, 0.7, 1e-6);
  EXPECT_GT(band.level, 0.0);
  const VoxelSolid offset = nodal_voxel_solid("G", 24, sheet, 0.7, NodalSheet::kOffset);
  EXPECT_NEAR(offset.porosity, 0.7, 1e-6);
  EXPECT_GT(offset.thickness, 0.0);
  // The band of a nodal sheet is thicker where |grad F| is small: not the same solid as the
  // constant-thickness offset at the same porosity.
  double differ = 0.0;
  for_each_cell(band.fraction, [&](int i, int j, int k) {
    differ += std::abs(band.fraction(i, j, k) - offset.fraction(i, j, k));
  });
  EXPECT_GT(differ / band.fraction.global_cells(), 1e-3);
}

}  // namespace
}  // namespace cmcsurf
