// The voxel stencil and the FFT preconditioner against their plain twins, and the
// preconditioner as the exact inverse of the homogeneous stencil.
#include "properties/voxel_operator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "properties/fft_preconditioner.h"
#include "properties/voxel_element.h"
#include "properties/operator_testing.h"

namespace cmcsurf::properties {
namespace {

std::vector<double> random_solid(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.5, 1.0);
  std::vector<double> s(std::size_t(n) * n * n);
  for (double& v : s) v = std::max(0.0, u(rng));  // a third void
  return s;
}

using testing::max_abs;
using testing::random_vec;

template <int D>
void expect_apply_matches_reference(int n, const typename VoxelOperator<D>::ElementMatrix& ke,
                                    double void_below) {
  const auto s = random_solid(n, 7 + n);
  VoxelOperator<D> op(n, s, ke, void_below);
  const Vec x = random_vec(op.size(), 11);
  Vec y(op.size()), y_ref(op.size());
  op.apply(x.data(), y.data());
  op.apply_ref(x.data(), y_ref.data());
  double diff = 0.0;
  for (std::size_t q = 0; q < y.size(); ++q) diff = std::max(diff, std::abs(y[q] - y_ref[q]));
  EXPECT_LT(diff, 1e-13 * max_abs(y_ref)) << "n = " << n << ", dofs = " << D;
}

// Even n (two colours) and odd n (the third pass for the last layer).
TEST(VoxelOperator, ApplyMatchesReference) {
  for (int n : {6, 7})
    for (double void_below : {0.0, 0.3}) {
      expect_apply_matches_reference<1>(n, conductivity_element(), void_below);
      expect_apply_matches_reference<3>(n, elasticity_element(0.3), void_below);
    }
}

// Element matrices: symmetric, and rigid translations (and, for elasticity, the affine
// fields' element forces summing to zero) are in their kernel.
TEST(VoxelOperator, ElementMatricesAnnihilateTranslations) {
  const auto k1 = conductivity_element();
  const auto k3 = elasticity_element(0.3);
  for (int a = 0; a < 8; ++a) {
    double row = 0.0;
    for (int b = 0; b < 8; ++b) {
      row += k1[a][b];
      EXPECT_DOUBLE_EQ(k1[a][b], k1[b][a]);
    }
    EXPECT_NEAR(row, 0.0, 1e-15);
  }
  for (int r = 0; r < 24; ++r)
    for (int c = 0; c < 3; ++c) {
      double row = 0.0;
      for (int b = 0; b < 8; ++b) row += k3[r][3 * b + c];
      EXPECT_NEAR(row, 0.0, 1e-15);
      EXPECT_NEAR(k3[r][c], k3[c][r], 1e-15);
    }
}

// Nodes touching no solid voxel are inactive; K x has no entries there.
TEST(VoxelOperator, NodesTouchingNoSolidAreInactive) {
  const int n = 6;
  std::vector<double> s(std::size_t(n) * n * n, 0.0);
  s[(2 * n + 2) * n + 2] = 0.5;  // one voxel: 8 active nodes
  VoxelOperator<3> op(n, s, elasticity_element(0.3));
  int active = 0;
  for (auto a : op.active_nodes()) active += a;
  EXPECT_EQ(active, 8);
  int scaled = 0;
  for (float d : op.node_scaling()) {
    if (d == 0.0f) continue;
    ++scaled;
    EXPECT_FLOAT_EQ(d, float(1.0 / std::sqrt(0.5 / 8.0)));
  }
  EXPECT_EQ(scaled, 8);
}

template <int D>
void expect_preconditioner_matches_reference(int n) {
  const auto s = random_solid(n, 3);
  VoxelOperator<D> op(n, s, typename VoxelOperator<D>::ElementMatrix{});  // for the scaling
  const std::vector<float> scaling = op.node_scaling();
  FftReferencePreconditioner pre(n, D, 0.6, 0.4, &scaling);
  const Vec r = random_vec(op.size(), 5);
  Vec z(op.size()), z_ref(op.size());
  pre.apply(r.data(), z.data());
  pre.apply_ref(r.data(), z_ref.data());
  double diff = 0.0;
  for (std::size_t q = 0; q < z.size(); ++q) diff = std::max(diff, std::abs(z[q] - z_ref[q]));
  EXPECT_LT(diff, 1e-12 * max_abs(z_ref)) << "n = " << n << ", dofs = " << D;
}

TEST(FftReferencePreconditioner, ApplyMatchesReference) {
  for (int n : {6, 7}) {
    expect_preconditioner_matches_reference<1>(n);
    expect_preconditioner_matches_reference<3>(n);
  }
}

// On a fully solid cell the preconditioner inverts the stencil: M^-1 K x = x - mean(x).
template <int D>
void expect_inverts_homogeneous_stencil(int n, double nu) {
  const std::vector<double> s(std::size_t(n) * n * n, 1.0);
  const Lame l = lame_of(nu);
  typename VoxelOperator<D>::ElementMatrix ke;
  if constexpr (D == 1)
    ke = conductivity_element();
  else
    ke = elasticity_element(nu);
  VoxelOperator<D> op(n, s, ke);
  const std::vector<float> scaling = op.node_scaling();  // 1 on a solid cell
  FftReferencePreconditioner pre(n, D, l.lambda, l.mu, &scaling);
  Vec x = random_vec(op.size(), 9);
  for (int c = 0; c < D; ++c) {  // remove the mean (the stencil's kernel)
    double mean = 0.0;
    for (std::size_t q = c; q < x.size(); q += D) mean += x[q];
    mean /= double(op.nodes());
    for (std::size_t q = c; q < x.size(); q += D) x[q] -= mean;
  }
  Vec kx(op.size()), back(op.size());
  op.apply(x.data(), kx.data());
  pre.apply(kx.data(), back.data());
  double diff = 0.0;
  for (std::size_t q = 0; q < x.size(); ++q) diff = std::max(diff, std::abs(back[q] - x[q]));
  EXPECT_LT(diff, 1e-12) << "n = " << n << ", dofs = " << D << ", nu = " << nu;
}

TEST(FftReferencePreconditioner, InvertsTheHomogeneousStencil) {
  for (int n : {4, 7, 8}) {
    expect_inverts_homogeneous_stencil<1>(n, 0.3);
    expect_inverts_homogeneous_stencil<3>(n, 0.3);
    expect_inverts_homogeneous_stencil<3>(n, -0.2);
  }
}

}  // namespace
}  // namespace cmcsurf::properties
