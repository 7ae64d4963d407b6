// The Stokes stencil and its preconditioner against their plain twins, the operator's symmetry,
// the wall distances of the cut cells, the preconditioner as the exact inverse of the shifted
// Laplacian of an open cell, and MINRES on a small indefinite system.
#include "properties/stokes_operator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "properties/minres.h"
#include "properties/stokes_preconditioner.h"
#include "properties/operator_testing.h"

namespace cmcsurf::properties {
namespace {

using testing::max_abs;
using testing::random_clamped_solid;
using testing::random_vec;

double max_diff(const Vec& a, const Vec& b) {
  double m = 0.0;
  for (std::size_t q = 0; q < a.size(); ++q) m = std::max(m, std::abs(a[q] - b[q]));
  return m;
}

double dot(const Vec& a, const Vec& b) {
  double s = 0.0;
  for (std::size_t q = 0; q < a.size(); ++q) s += a[q] * b[q];
  return s;
}

// Even and odd n; the random x has values on solid faces too, which both must ignore.
TEST(StokesOperator, ApplyMatchesReference) {
  for (int n : {5, 6}) {
    const auto s = random_clamped_solid(n, 3 + n);
    const StokesOperator op(n, s, 1.7, 0.05);
    EXPECT_GT(op.fluid_faces(), 0u);
    EXPECT_LT(op.fluid_faces(), 3 * op.cells());
    const Vec x = random_vec(op.size(), 5);
    Vec y(op.size()), y_ref(op.size());
    op.apply(x.data(), y.data());
    op.apply_ref(x.data(), y_ref.data());
    EXPECT_LT(max_diff(y, y_ref), 1e-6 * max_abs(y_ref)) << "n = " << n;  // float diagonal
  }
}

// y += K x and x . K x in one pass: the same as apply and a dot product.
TEST(StokesOperator, ApplyAddMatchesApply) {
  const int n = 6;
  const auto s = random_clamped_solid(n, 21);
  const StokesOperator op(n, s);
  const Vec x = random_vec(op.size(), 3), y0 = random_vec(op.size(), 4);
  Vec kx(op.size()), y = y0;
  op.apply(x.data(), kx.data());
  const double xkx = op.apply_add(x.data(), y.data());
  Vec expected(op.size());
  for (std::size_t q = 0; q < y.size(); ++q) expected[q] = y0[q] + kx[q];
  EXPECT_LT(max_diff(y, expected), 1e-13 * max_abs(expected));
  EXPECT_NEAR(xkx, dot(x, kx), 1e-12 * std::abs(dot(x, kx)));
}

// x^T K y = y^T K x for vectors that vanish on solid faces and inactive voxels (the space
// the iteration lives in).
TEST(StokesOperator, IsSymmetric) {
  const int n = 6;
  const auto s = random_clamped_solid(n, 9);
  const StokesOperator op(n, s);
  auto restrict_to_fluid = [&](Vec& v) {
    for (int c = 0; c < 3; ++c)
      for (std::size_t q = 0; q < op.cells(); ++q)
        if (!op.fluid_face(c, q)) v[c * op.cells() + q] = 0.0;
    for (std::size_t q = 0; q < op.cells(); ++q)
      if (!op.active_cells()[q]) v[3 * op.cells() + q] = 0.0;
  };
  Vec x = random_vec(op.size(), 1), y = random_vec(op.size(), 2);
  restrict_to_fluid(x);
  restrict_to_fluid(y);
  Vec kx(op.size()), ky(op.size());
  op.apply(x.data(), kx.data());
  op.apply(y.data(), ky.data());
  EXPECT_NEAR(dot(y, kx), dot(x, ky), 1e-12 * std::abs(dot(y, kx)));
}

// A plane wall at y = w cut through a voxel: the face level set is the exact signed distance
// in the cut voxel, so the wall distance is exact from either side of the link.
TEST(StokesOperator, WallDistanceOfAPlane) {
  // Fluid face centre at y = 2.5, wall at 3.3: psi = 0.5 (uncut), next face psi = -0.2 (cut).
  EXPECT_NEAR(wall_distance(0.5, -0.2), 0.8, 1e-15);
  // Fluid face cut: wall at 3.1 from 2.5 when its own psi is 0.4 (fraction 0.9 pore).
  EXPECT_NEAR(wall_distance(0.4, -0.5), 0.4, 1e-15);
  // Both cut: linear interpolation. Neither: the wall on the voxel face between them.
  EXPECT_NEAR(wall_distance(0.2, -0.2), 0.5, 1e-15);
  EXPECT_NEAR(wall_distance(0.5, -0.5), 0.5, 1e-15);
}

TEST(StokesPreconditioner, ApplyMatchesReference) {
  for (int n : {5, 6}) {
    const auto s = random_clamped_solid(n, 13 + n);
    const StokesOperator op(n, s, 0.7);
    const StokesPreconditioner pre(op, 0.3);
    const Vec r = random_vec(op.size(), 17);
    Vec z(op.size()), z_ref(op.size());
    pre.apply(r.data(), z.data());
    pre.apply_ref(r.data(), z_ref.data());
    EXPECT_LT(max_diff(z, z_ref), 1e-12 * max_abs(z_ref)) << "n = " << n;
  }
}

// An open cell (no solid): A = mu (-Laplacian) and D = I, so M^-1 (A + mu sigma) u = u.
TEST(StokesPreconditioner, InvertsTheShiftedLaplacianOfAnOpenCell) {
  for (int n : {4, 7, 8}) {
    const std::vector<double> s(std::size_t(n) * n * n, 0.0);
    const double mu = 2.5, sigma = 0.4;
    const StokesOperator op(n, s, mu);
    const StokesPreconditioner pre(op, sigma);
    Vec u = random_vec(op.size(), 23);
    for (std::size_t q = 3 * op.cells(); q < op.size(); ++q) u[q] = 0.0;  // p = 0
    Vec au(op.size()), z(op.size());
    op.apply(u.data(), au.data());
    for (std::size_t q = 0; q < 3 * op.cells(); ++q) au[q] += mu * sigma * u[q];
    pre.apply(au.data(), z.data());
    for (std::size_t q = 3 * op.cells(); q < op.size(); ++q) z[q] = 0.0;
    EXPECT_LT(max_diff(z, u), 1e-12) << "n = " << n;
  }
}

// A random symmetric indefinite 40 x 40 system with a diagonal SPD preconditioner.
TEST(Minres, SolvesASymmetricIndefiniteSystem) {
  const std::size_t m = 40;
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> a(m * m), d(m);
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t j = 0; j <= i; ++j) a[i * m + j] = a[j * m + i] = 0.1 * u(rng);
    a[i * m + i] += i % 2 ? 3.0 : -2.0;  // half the spectrum negative
    d[i] = 0.5 + std::abs(u(rng));
  }
  const Vec b = random_vec(m, 31);
  Vec x(m), v_prev(m), v(b), z(m), w_prev(m), w(m);
  auto apply = [&](const double* p, double* y) {
    for (std::size_t i = 0; i < m; ++i) {
      y[i] = 0.0;
      for (std::size_t j = 0; j < m; ++j) y[i] += a[i * m + j] * p[j];
    }
  };
  auto apply_add = [&](const double* p, double* y) {
    Vec ap(m);
    apply(p, ap.data());
    double pap = 0.0;
    for (std::size_t i = 0; i < m; ++i) {
      y[i] += ap[i];
      pap += p[i] * ap[i];
    }
    return pap;
  };
  const CgStats st = minres(
      m, apply_add, [&](const double* r, double* y) {
        for (std::size_t i = 0; i < m; ++i) y[i] = r[i] / d[i];
      },
      x.data(), MinresWork{v_prev.data(), v.data(), z.data(), w_prev.data(), w.data()},
      CgOptions{1e-12, 0.0, 200});
  EXPECT_TRUE(st.converged);
  EXPECT_LE(st.iterations, int(m) + 5);
  Vec ax(m);
  apply(x.data(), ax.data());
  EXPECT_LT(max_diff(ax, b), 1e-10 * max_abs(b));
}

}  // namespace
}  // namespace cmcsurf::properties
