#include "cahn_hilliard/operator.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "grid/stencil.h"
#include "multigrid/transfer.h"

namespace cmcsurf {

namespace {

// Solves the 2x2 system (A.3)-(A.4) at one cell given neighbour sums.
struct PointSolve {
  double inv_dt, inv_h2, eps2;
  inline void operator()(double& phi, double& nu, double sum_phi, double sum_nu, double s_phi,
                         double s_nu) const {
    const double phim = phi;
    const double df = ch_df(phim);
    const double r1 = s_phi + sum_nu * inv_h2;
    const double r2 = s_nu + ch_f(phim) - df * phim - eps2 * inv_h2 * sum_phi;
    const double a12 = 6.0 * inv_h2;
    const double b = df + 6.0 * eps2 * inv_h2;  // -a21
    const double inv_det = 1.0 / (inv_dt + a12 * b);
    phi = (r1 - a12 * r2) * inv_det;
    nu = (inv_dt * r2 + b * r1) * inv_det;
  }
};

}  // namespace

namespace {

// Row kernels. With two outputs and neighbour reads at run-time strides g++ needs more than its
// limit of 10 run-time alias checks and leaves such a loop scalar; the rows never overlap, which
// `#pragma GCC ivdep` (and __restrict, kept where the function is not inlined) tells it.
inline void source_row(const double* __restrict p, double* __restrict s,
                       double* __restrict t, int nx, std::ptrdiff_t sy, std::ptrdiff_t sz,
                       double inv_dt, double inv_h2) {
#pragma GCC ivdep
  for (int i = 0; i < nx; ++i) {
    s[i] = p[i] * inv_dt - 0.25 * laplacian(p + i, sy, sz, inv_h2);
    t[i] = 0.0;
  }
}

// out = rhs - NSO(u) on one row.
inline void residual_row(const double* __restrict ph, const double* __restrict nv,
                         const double* __restrict r1, const double* __restrict r2,
                         double* __restrict o1, double* __restrict o2, int nx, std::ptrdiff_t sy,
                         std::ptrdiff_t sz, double inv_dt, double inv_h2, double eps2) {
#pragma GCC ivdep
  for (int i = 0; i < nx; ++i) {
    const double a1 = ph[i] * inv_dt - laplacian(nv + i, sy, sz, inv_h2);
    const double a2 = -ch_f(ph[i]) + eps2 * laplacian(ph + i, sy, sz, inv_h2) + nv[i];
    o1[i] = r1[i] - a1;
    o2[i] = r2[i] - a2;
  }
}

// residual_row for a phi and a nu of different ghost widths (strides): the same arithmetic.
inline void residual_row_strided(const double* __restrict ph, const double* __restrict nv,
                                 const double* __restrict r1, const double* __restrict r2,
                                 double* __restrict o1, double* __restrict o2, int nx,
                                 std::ptrdiff_t sy, std::ptrdiff_t sz, std::ptrdiff_t nu_sy,
                                 std::ptrdiff_t nu_sz, double inv_dt, double inv_h2,
                                 double eps2) {
#pragma GCC ivdep
  for (int i = 0; i < nx; ++i) {
    const double a1 = ph[i] * inv_dt - laplacian(nv + i, nu_sy, nu_sz, inv_h2);
    const double a2 = -ch_f(ph[i]) + eps2 * laplacian(ph + i, sy, sz, inv_h2) + nv[i];
    o1[i] = r1[i] - a1;
    o2[i] = r2[i] - a2;
  }
}

// out = NSO(u) on one row.
inline void apply_row(const double* __restrict ph, const double* __restrict nv,
                      double* __restrict o1, double* __restrict o2, int nx, std::ptrdiff_t sy,
                      std::ptrdiff_t sz, double inv_dt, double inv_h2, double eps2) {
#pragma GCC ivdep
  for (int i = 0; i < nx; ++i) {
    o1[i] = ph[i] * inv_dt - laplacian(nv + i, sy, sz, inv_h2);
    o2[i] = -ch_f(ph[i]) + eps2 * laplacian(ph + i, sy, sz, inv_h2) + nv[i];
  }
}

}  // namespace

void ch_source(const Field& phi_n, double dt, Field& src_phi, Field& src_nu) {
  CMCSURF_DCHECK(halo_is_current(phi_n));
  CMCSURF_CHECK(src_phi.size() == phi_n.size() && src_nu.size() == phi_n.size());
  const int n = phi_n.n(), nx = phi_n.nx(), ny = phi_n.ny(), nz = phi_n.nz();
  const double inv_h2 = double(n) * n, inv_dt = 1.0 / dt;
  const std::ptrdiff_t sy = phi_n.stride_y(), sz = phi_n.stride_z();
#pragma omp parallel for schedule(static) if (nx >= kParallelMinN)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      source_row(&phi_n(0, j, k), &src_phi(0, j, k), &src_nu(0, j, k), nx, sy, sz, inv_dt,
                 inv_h2);
}

namespace {

// Delta_d f at (i, j, k), written out.
double laplacian_ref(const Field& f, int i, int j, int k) {
  const double h = 1.0 / f.n();
  return (f(i + 1, j, k) + f(i - 1, j, k) + f(i, j + 1, k) + f(i, j - 1, k) + f(i, j, k + 1) +
          f(i, j, k - 1) - 6.0 * f(i, j, k)) /
         (h * h);
}

}  // namespace

void ch_source_ref(const Field& phi_n, double dt, Field& src_phi, Field& src_nu) {
  CMCSURF_DCHECK(halo_is_current(phi_n));
  for_each_cell(phi_n, [&](int i, int j, int k) {
    src_phi(i, j, k) = phi_n(i, j, k) / dt - 0.25 * laplacian_ref(phi_n, i, j, k);
    src_nu(i, j, k) = 0.0;
  });
}

void ch_nu_from_phi(const Field& phi, double epsilon, Field& nu) {
  CMCSURF_DCHECK(halo_is_current(phi));
  CMCSURF_CHECK(nu.size() == phi.size());
  const int n = phi.n(), nx = phi.nx(), ny = phi.ny(), nz = phi.nz();
  const double inv_h2 = double(n) * n, eps2 = epsilon * epsilon;
  const std::ptrdiff_t sy = phi.stride_y(), sz = phi.stride_z();
#pragma omp parallel for schedule(static) if (nx >= kParallelMinN)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      const double* ph = &phi(0, j, k);
      double* nv = &nu(0, j, k);
      for (int i = 0; i < nx; ++i) nv[i] = ch_f(ph[i]) - eps2 * laplacian(ph + i, sy, sz, inv_h2);
    }
}

double ch_defect_norm(const Field& d_phi, const Field& d_nu, double dt) {
  CMCSURF_CHECK(d_nu.size() == d_phi.size());
  const int nx = d_phi.nx(), ny = d_phi.ny(), nz = d_phi.nz();
  double s1 = 0.0, s2 = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : s1, s2) if (nx >= kParallelMinN)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      const double* a = &d_phi(0, j, k);
      const double* b = &d_nu(0, j, k);
      for (int i = 0; i < nx; ++i) {
        s1 += a[i] * a[i];
        s2 += b[i] * b[i];
      }
    }
  double sums[2] = {s1, s2};
  d_phi.sum_over_ranks(sums, 2);
  return std::sqrt((dt * dt * sums[0] + sums[1]) / d_phi.global_cells());
}

double ch_defect_norm_ref(const Field& d_phi, const Field& d_nu, double dt) {
  double sums[2] = {0.0, 0.0};
  for_each_cell(d_phi, [&](int i, int j, int k) {
    const double a = dt * d_phi(i, j, k), b = d_nu(i, j, k);
    sums[0] += a * a;
    sums[1] += b * b;
  });
  d_phi.sum_over_ranks(sums, 2);
  return std::sqrt((sums[0] + sums[1]) / d_phi.global_cells());
}

void nso_residual(const Field& phi, const Field& nu, const Field* rhs_phi, const Field* rhs_nu,
                  const ChParams& p, Field& out_phi, Field& out_nu) {
  CMCSURF_DCHECK(halo_is_current(phi) && halo_is_current(nu));
  CMCSURF_CHECK(nu.size() == phi.size() && out_phi.size() == phi.size() &&
                out_nu.size() == phi.size() && (!rhs_phi || rhs_phi->size() == phi.size()) &&
                (!rhs_nu || rhs_nu->size() == phi.size()) && (!rhs_phi == !rhs_nu));
  const int n = phi.n(), nx = phi.nx(), ny = phi.ny(), nz = phi.nz();
  const double inv_h2 = double(n) * n, inv_dt = 1.0 / p.dt, eps2 = p.epsilon * p.epsilon;
  const std::ptrdiff_t sy = phi.stride_y(), sz = phi.stride_z();
  if (rhs_phi) {
#pragma omp parallel for schedule(static) if (nx >= kParallelMinN)
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        residual_row(&phi(0, j, k), &nu(0, j, k), &(*rhs_phi)(0, j, k), &(*rhs_nu)(0, j, k),
                     &out_phi(0, j, k), &out_nu(0, j, k), nx, sy, sz, inv_dt, inv_h2, eps2);
  } else {
#pragma omp parallel for schedule(static) if (nx >= kParallelMinN)
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        apply_row(&phi(0, j, k), &nu(0, j, k), &out_phi(0, j, k), &out_nu(0, j, k), nx, sy, sz,
                  inv_dt, inv_h2, eps2);
  }
}

namespace {

// nso_residual_norm's pass; with kMean also the sum of phi's interior in mean's order (rows by
// a SIMD reduction, their sum per plane, the planes into the thread's sum).
template <bool kMean>
double residual_norm_pass(const Field& phi, const Field& nu, const Field& rhs_phi,
                          const Field& rhs_nu, const ChParams& p, double* phi_mean) {
  CMCSURF_DCHECK(halo_is_current(phi) && halo_is_current(nu));
  CMCSURF_CHECK(nu.size() == phi.size() && rhs_phi.size() == phi.size() &&
                rhs_nu.size() == phi.size());
  const int n = phi.n(), nx = phi.nx(), ny = phi.ny(), nz = phi.nz();
  const double inv_h2 = double(n) * n, inv_dt = 1.0 / p.dt, eps2 = p.epsilon * p.epsilon;
  const std::ptrdiff_t sy = phi.stride_y(), sz = phi.stride_z();
  double s1 = 0.0, s2 = 0.0, sm = 0.0;
  // The loops and the reduction are ch_defect_norm's, so the sums come out in its order (and
  // mean's: both split the planes alike, serially below kParallelMinN).
#pragma omp parallel reduction(+ : s1, s2, sm) if (nx >= kParallelMinN)
  {
    std::vector<double> row(2 * std::size_t(nx));
    double* a = row.data();
    double* b = a + nx;
#pragma omp for schedule(static)
    for (int k = 0; k < nz; ++k) {
      double plane = 0.0;
      for (int j = 0; j < ny; ++j) {
        const double* ph = &phi(0, j, k);
        residual_row(ph, &nu(0, j, k), &rhs_phi(0, j, k), &rhs_nu(0, j, k), a, b, nx, sy, sz,
                     inv_dt, inv_h2, eps2);
        for (int i = 0; i < nx; ++i) {
          s1 += a[i] * a[i];
          s2 += b[i] * b[i];
        }
        if constexpr (kMean) {
          double s = 0.0;
#pragma omp simd reduction(+ : s)
          for (int i = 0; i < nx; ++i) s += ph[i];
          plane += s;
        }
      }
      if constexpr (kMean) sm += plane;
    }
  }
  double sums[3] = {s1, s2, sm};
  phi.sum_over_ranks(sums, kMean ? 3 : 2);
  if constexpr (kMean) *phi_mean = sums[2] / phi.global_cells();
  return std::sqrt((p.dt * p.dt * sums[0] + sums[1]) / phi.global_cells());
}

}  // namespace

double nso_residual_norm(const Field& phi, const Field& nu, const Field& rhs_phi,
                         const Field& rhs_nu, const ChParams& p) {
  return residual_norm_pass<false>(phi, nu, rhs_phi, rhs_nu, p, nullptr);
}

double nso_residual_norm_mean(const Field& phi, const Field& nu, const Field& rhs_phi,
                              const Field& rhs_nu, const ChParams& p, double& phi_mean) {
  return residual_norm_pass<true>(phi, nu, rhs_phi, rhs_nu, p, &phi_mean);
}

double nso_residual_norm_mean_ref(const Field& phi, const Field& nu, const Field& rhs_phi,
                                  const Field& rhs_nu, const ChParams& p, double& phi_mean) {
  phi_mean = mean(phi);
  return nso_residual_norm(phi, nu, rhs_phi, rhs_nu, p);
}

double ch_source_first_defect(const Field& phi_n, const Field& nu, const ChParams& p,
                              Field& src_phi, Field& src_nu, Field& guess,
                              const StepStartExtras& extras) {
  CMCSURF_DCHECK(halo_is_current(phi_n) && halo_is_current(nu));
  CMCSURF_CHECK(nu.size() == phi_n.size() && src_phi.size() == phi_n.size() &&
                src_nu.size() == phi_n.size() && guess.size() == phi_n.size());
  Field* const phi_copy = extras.phi_copy;
  Field* const nu_copy = extras.nu_copy;
  const bool want_mean = extras.phi_mean != nullptr;
  CMCSURF_CHECK((!phi_copy || phi_copy->size() == phi_n.size()) &&
                (!nu_copy || nu_copy->size() == phi_n.size()));
  const int n = phi_n.n(), nx = phi_n.nx(), ny = phi_n.ny(), nz = phi_n.nz();
  const double inv_h2 = double(n) * n, inv_dt = 1.0 / p.dt, eps2 = p.epsilon * p.epsilon;
  const std::ptrdiff_t sy = phi_n.stride_y(), sz = phi_n.stride_z();
  const std::ptrdiff_t nu_sy = nu.stride_y(), nu_sz = nu.stride_z();  // may differ from phi_n's
  const std::size_t row_bytes = sizeof(double) * nx;
  double s1 = 0.0, s2 = 0.0, sm = 0.0;
  // nso_residual_norm's loops and reduction (its sums, in its order); the guess's interior is
  // phi_n's, so its defect is taken from phi_n, whose ghosts are the guess's after an exchange.
  // The mean's sums are mean's (the same split of the planes).
#pragma omp parallel reduction(+ : s1, s2, sm) if (nx >= kParallelMinN)
  {
    std::vector<double> row(2 * std::size_t(nx));
    double* a = row.data();
    double* b = a + nx;
#pragma omp for schedule(static)
    for (int k = 0; k < nz; ++k) {
      double plane = 0.0;
      for (int j = 0; j < ny; ++j) {
        const double* ph = &phi_n(0, j, k);
        const double* nv = &nu(0, j, k);
        double* r1 = &src_phi(0, j, k);
        double* r2 = &src_nu(0, j, k);
        source_row(ph, r1, r2, nx, sy, sz, inv_dt, inv_h2);
        std::memcpy(&guess(0, j, k), ph, row_bytes);
        if (phi_copy) std::memcpy(&(*phi_copy)(0, j, k), ph, row_bytes);
        if (nu_copy) std::memcpy(&(*nu_copy)(0, j, k), nv, row_bytes);
        residual_row_strided(ph, nv, r1, r2, a, b, nx, sy, sz, nu_sy, nu_sz, inv_dt, inv_h2,
                             eps2);
        for (int i = 0; i < nx; ++i) {
          s1 += a[i] * a[i];
          s2 += b[i] * b[i];
        }
        if (want_mean) {
          double s = 0.0;
#pragma omp simd reduction(+ : s)
          for (int i = 0; i < nx; ++i) s += ph[i];
          plane += s;
        }
      }
      sm += plane;
    }
  }
  double sums[3] = {s1, s2, sm};
  phi_n.sum_over_ranks(sums, want_mean ? 3 : 2);
  if (want_mean) *extras.phi_mean = sums[2] / phi_n.global_cells();
  return std::sqrt((p.dt * p.dt * sums[0] + sums[1]) / phi_n.global_cells());
}

double ch_source_first_defect_ref(const Field& phi_n, const Field& nu, const ChParams& p,
                                  Field& src_phi, Field& src_nu, Field& guess,
                                  const StepStartExtras& extras) {
  if (extras.phi_mean) *extras.phi_mean = mean(phi_n);
  if (extras.phi_copy) copy_interior(phi_n, *extras.phi_copy);
  if (extras.nu_copy) copy_interior(nu, *extras.nu_copy);
  ch_source(phi_n, p.dt, src_phi, src_nu);
  copy_interior(phi_n, guess);
  guess.exchange_halo();
  return nso_residual_norm(guess, nu, src_phi, src_nu, p);
}

void nso_residual_restrict(const Field& phi, const Field& nu, const Field& rhs_phi,
                           const Field& rhs_nu, const ChParams& p, Field& coarse_phi,
                           Field& coarse_nu) {
  CMCSURF_DCHECK(halo_is_current(phi) && halo_is_current(nu));
  CMCSURF_CHECK(nu.size() == phi.size() && rhs_phi.size() == phi.size() &&
                rhs_nu.size() == phi.size() && coarse_nu.size() == coarse_phi.size());
  for (int a = 0; a < 3; ++a)
    CMCSURF_CHECK(phi.size()[a] == 2 * coarse_phi.size()[a] &&
                  phi.offset()[a] == 2 * coarse_phi.offset()[a]);
  CMCSURF_CHECK(phi.n() == 2 * coarse_phi.n());
  const int n = phi.n(), nx = phi.nx();
  const int ncx = coarse_phi.nx(), ncy = coarse_phi.ny(), ncz = coarse_phi.nz();
  const double inv_h2 = double(n) * n, inv_dt = 1.0 / p.dt, eps2 = p.epsilon * p.epsilon;
  const std::ptrdiff_t sy = phi.stride_y(), sz = phi.stride_z();
#pragma omp parallel if (nx >= kParallelMinN)
  {
    // The defect of the four fine rows (dj, dk) under one coarse row, per component.
    std::vector<double> rows(8 * std::size_t(nx));
#pragma omp for schedule(static)
    for (int k = 0; k < ncz; ++k)
      for (int j = 0; j < ncy; ++j) {
        for (int q = 0; q < 4; ++q) {
          const int fj = 2 * j + (q & 1), fk = 2 * k + (q >> 1);
          residual_row(&phi(0, fj, fk), &nu(0, fj, fk), &rhs_phi(0, fj, fk), &rhs_nu(0, fj, fk),
                       &rows[std::size_t(q) * nx], &rows[std::size_t(q + 4) * nx], nx, sy, sz,
                       inv_dt, inv_h2, eps2);
        }
        for (int c = 0; c < 2; ++c) {
          // Rows (j, k), (j+1, k), (j, k+1), (j+1, k+1), summed as restrict_average sums them.
          const double* r0 = &rows[std::size_t(4 * c) * nx];
          const double* r1 = r0 + nx;
          const double* r2 = r1 + nx;
          const double* r3 = r2 + nx;
          double* out = c == 0 ? &coarse_phi(0, j, k) : &coarse_nu(0, j, k);
          for (int i = 0; i < ncx; ++i) {
            const int f = 2 * i;
            out[i] = 0.125 * ((r0[f] + r0[f + 1]) + (r1[f] + r1[f + 1]) + (r2[f] + r2[f + 1]) +
                              (r3[f] + r3[f + 1]));
          }
        }
      }
  }
}

void nso_residual_restrict_ref(const Field& phi, const Field& nu, const Field& rhs_phi,
                               const Field& rhs_nu, const ChParams& p, Field& coarse_phi,
                               Field& coarse_nu) {
  Field d_phi = Field::like(phi, 0), d_nu = Field::like(phi, 0);
  nso_residual_ref(phi, nu, &rhs_phi, &rhs_nu, p, d_phi, d_nu);
  restrict_average_ref(d_phi, coarse_phi);
  restrict_average_ref(d_nu, coarse_nu);
}

double nso_residual_norm_ref(const Field& phi, const Field& nu, const Field& rhs_phi,
                             const Field& rhs_nu, const ChParams& p) {
  Field d_phi = Field::like(phi, 0), d_nu = Field::like(phi, 0);
  nso_residual_ref(phi, nu, &rhs_phi, &rhs_nu, p, d_phi, d_nu);
  return ch_defect_norm_ref(d_phi, d_nu, p.dt);
}

void nso_residual_ref(const Field& phi, const Field& nu, const Field* rhs_phi,
                      const Field* rhs_nu, const ChParams& p, Field& out_phi, Field& out_nu) {
  CMCSURF_DCHECK(halo_is_current(phi) && halo_is_current(nu));
  const double eps = p.epsilon, dt = p.dt;
  for_each_cell(phi, [&](int i, int j, int k) {
    const double x = phi(i, j, k);
    const double a1 = x / dt - laplacian_ref(nu, i, j, k);
    const double a2 = -(x * x * x - 1.5 * x * x + 0.75 * x) +
                      eps * eps * laplacian_ref(phi, i, j, k) + nu(i, j, k);
    if (rhs_phi) {
      out_phi(i, j, k) = (*rhs_phi)(i, j, k) - a1;
      out_nu(i, j, k) = (*rhs_nu)(i, j, k) - a2;
    } else {
      out_phi(i, j, k) = a1;
      out_nu(i, j, k) = a2;
    }
  });
}

namespace {

// Relaxes the cells i = first, first + step, ... of row (j, k) by (A.3)-(A.4).
inline void relax_row(Field& phi, Field& nu, const Field& src_phi, const Field& src_nu,
                      const PointSolve& solve, int j, int k, int first, int step) {
  const int n = phi.nx();  // this block's row length
  const std::ptrdiff_t sy = phi.stride_y(), sz = phi.stride_z();
  double* ph = &phi(0, j, k);
  double* nv = &nu(0, j, k);
  const double* s1 = &src_phi(0, j, k);
  const double* s2 = &src_nu(0, j, k);
  if (step == 1) {  // lexicographic: each cell sees its updated left neighbour
    for (int i = first; i < n; ++i)
      solve(ph[i], nv[i], neighbour_sum(ph + i, sy, sz), neighbour_sum(nv + i, sy, sz), s1[i],
            s2[i]);
    return;
  }
  // One colour: its cells' neighbours all have the other colour, so the updates of the row's
  // cells of this colour can be computed from stored values into a contiguous buffer (strided
  // loads, unit-stride SIMD arithmetic: the division per cell bounds this kernel) and stored
  // back afterwards.
  constexpr int kChunk = 128;
  alignas(64) double new_phi[kChunk];
  alignas(64) double new_nu[kChunk];
  for (int i0 = first; i0 < n; i0 += 2 * kChunk) {
    const int m = std::min(kChunk, (n - i0 + 1) / 2);
    const double* p0 = ph + i0;
    const double* n0 = nv + i0;
    const double* t1 = s1 + i0;
    const double* t2 = s2 + i0;
    for (int c = 0; c < m; ++c) {
      double a = p0[2 * c], b = n0[2 * c];
      solve(a, b, neighbour_sum(p0 + 2 * c, sy, sz), neighbour_sum(n0 + 2 * c, sy, sz),
            t1[2 * c], t2[2 * c]);
      new_phi[c] = a;
      new_nu[c] = b;
    }
    double* pw = ph + i0;
    double* nw = nv + i0;
    for (int c = 0; c < m; ++c) {
      pw[2 * c] = new_phi[c];
      nw[2 * c] = new_nu[c];
    }
  }
}

}  // namespace

void smooth_color(Field& phi, Field& nu, const Field& src_phi, const Field& src_nu,
                  const ChParams& p, int colour) {
  CMCSURF_DCHECK(halo_is_current(phi) && halo_is_current(nu));
  CMCSURF_CHECK(nu.size() == phi.size() && src_phi.size() == phi.size() &&
                src_nu.size() == phi.size());
  const int n = phi.n(), ny = phi.ny(), nz = phi.nz();
  const int parity = colour + phi.offset_parity();  // colour of global i + j + k
  const PointSolve solve{1.0 / p.dt, double(n) * n, p.epsilon * p.epsilon};
#pragma omp parallel for schedule(static) if (phi.nx() >= kParallelMinN)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      relax_row(phi, nu, src_phi, src_nu, solve, j, k, (j + k + parity) & 1, 2);
}

namespace {

// Periodic wrap of the x and y ghost layers of plane k (as the halo plan does for the block).
void wrap_plane_xy(Field& f, int k) {
  const int n = f.n(), g = f.ghost();
  for (int j = 0; j < n; ++j) {
    double* row = &f(0, j, k);
    for (int l = 1; l <= g; ++l) {
      row[-l] = row[n - l];
      row[n - 1 + l] = row[l - 1];
    }
  }
  for (int l = 1; l <= g; ++l) {
    std::copy_n(&f(-g, n - l, k), n + 2 * g, &f(-g, -l, k));
    std::copy_n(&f(-g, l - 1, k), n + 2 * g, &f(-g, n - 1 + l, k));
  }
}

// Periodic wrap of the z ghost planes (whole padded planes).
void wrap_planes_z(Field& f) {
  const int n = f.n(), g = f.ghost();
  const std::ptrdiff_t plane = f.stride_z();
  for (int l = 1; l <= g; ++l) {
    std::copy_n(&f(-g, -g, n - l), plane, &f(-g, -g, -l));
    std::copy_n(&f(-g, -g, l - 1), plane, &f(-g, -g, n - 1 + l));
  }
}

}  // namespace

void smooth_red_black_fused(Field& phi, Field& nu, const Field& src_phi, const Field& src_nu,
                            const ChParams& p, int sweeps) {
  if (!phi.whole()) throw std::logic_error("smooth_red_black_fused on a block of a split grid");
  CMCSURF_DCHECK(halo_is_current(phi) && halo_is_current(nu));
  const int n = phi.n();
  // Stage s relaxes colour s % 2 of sweep s / 2. Stage s of plane k reads stage s - 1 of planes
  // k-1, k, k+1 and must run before stage s + 1 of them, so a wavefront that does stage s of
  // plane k - s at step k keeps each cell's update order; a slab of 2 S planes per thread keeps
  // the boundary work of neighbouring slabs apart.
  const int stages = 2 * sweeps;
  CMCSURF_CHECK(sweeps >= 1 && n % 2 == 0 && (sweeps == 1 || n >= 2 * stages));
  CMCSURF_CHECK(nu.size() == phi.size() && src_phi.size() == phi.size() &&
                src_nu.size() == phi.size());
  const PointSolve solve{1.0 / p.dt, double(n) * n, p.epsilon * p.epsilon};
  const std::ptrdiff_t plane = phi.stride_z();
  const int g = phi.ghost();
  // Relaxes one stage of plane k (0 <= k < n) and refreshes its x/y ghosts while it is in cache.
  auto relax_plane = [&](int k, int stage) {
    const int colour = stage & 1;
    for (int j = 0; j < n; ++j)
      relax_row(phi, nu, src_phi, src_nu, solve, j, k, (j + k + colour) & 1, 2);
    wrap_plane_xy(phi, k);
    wrap_plane_xy(nu, k);
  };
  const int threads =
      n >= kParallelMinN ? std::max(1, std::min(omp_get_max_threads(), n / (2 * stages))) : 1;
#pragma omp parallel num_threads(threads)
  {
    const int t = omp_get_thread_num(), nt = omp_get_num_threads();
    const int k0 = int(std::int64_t(n) * t / nt), k1 = int(std::int64_t(n) * (t + 1) / nt);
    // 1) Inside the slab: stage s on planes k0 + s .. k1 - 1 - s, whose inputs all lie in the
    // slab (stage 0 reads the neighbours' planes and the z ghosts as they were on entry).
    for (int step = k0; step < k1 + stages - 1; ++step)
      for (int s = 0; s < stages; ++s) {
        const int k = step - s;
        if (k >= k0 + s && k <= k1 - 1 - s) relax_plane(k, s);
      }
#pragma omp barrier
#pragma omp single
    {
      wrap_planes_z(phi);
      wrap_planes_z(nu);
    }
    // 2) Each thread finishes the triangle around its slab's first plane b: stage s on planes
    // b - s .. b + s - 1 (periodic), in the same wavefront order. Planes 0 and n - 1 refresh the
    // ghost plane the other one reads after each stage.
    const int b = k0;
    for (int step = b; step <= b + 2 * stages - 3; ++step)
      for (int s = 1; s < stages; ++s) {
        const int v = step - s;
        if (v < b - s || v > b + s - 1) continue;
        const int k = (v + n) % n;
        relax_plane(k, s);
        if (k == 0) {
          std::copy_n(&phi(-g, -g, 0), plane, &phi(-g, -g, n));
          std::copy_n(&nu(-g, -g, 0), plane, &nu(-g, -g, n));
        }
        if (k == n - 1) {
          std::copy_n(&phi(-g, -g, n - 1), plane, &phi(-g, -g, -1));
          std::copy_n(&nu(-g, -g, n - 1), plane, &nu(-g, -g, -1));
        }
      }
#pragma omp barrier
#pragma omp single
    {  // planes near 0 and n - 1 changed after the first z wrap
      wrap_planes_z(phi);
      wrap_planes_z(nu);
    }
  }
}

namespace {

// (A.3)-(A.4) at cell (i,j,k) with whatever neighbour values are stored now, by Cramer's rule.
void relax_cell_ref(Field& phi, Field& nu, const Field& src_phi, const Field& src_nu,
                    const ChParams& p, int i, int j, int k) {
  const double h = 1.0 / phi.n(), eps = p.epsilon, dt = p.dt;
  auto nb = [&](const Field& f) {
    return f(i + 1, j, k) + f(i - 1, j, k) + f(i, j + 1, k) + f(i, j - 1, k) + f(i, j, k + 1) +
           f(i, j, k - 1);
  };
  const double m = phi(i, j, k);
  const double f = m * m * m - 1.5 * m * m + 0.75 * m;
  const double df = 3.0 * m * m - 3.0 * m + 0.75;
  // [ 1/dt            6/h^2 ] [phi]   [ src_phi + sum(nu)/h^2                        ]
  // [ -(df+6eps^2/h^2)  1   ] [nu ] = [ src_nu + f - df m - eps^2 sum(phi)/h^2        ]
  const double a11 = 1.0 / dt, a12 = 6.0 / (h * h);
  const double a21 = -(df + 6.0 * eps * eps / (h * h)), a22 = 1.0;
  const double b1 = src_phi(i, j, k) + nb(nu) / (h * h);
  const double b2 = src_nu(i, j, k) + f - df * m - eps * eps * nb(phi) / (h * h);
  const double det = a11 * a22 - a12 * a21;
  phi(i, j, k) = (b1 * a22 - a12 * b2) / det;
  nu(i, j, k) = (a11 * b2 - a21 * b1) / det;
}

}  // namespace

void smooth_color_ref(Field& phi, Field& nu, const Field& src_phi, const Field& src_nu,
                      const ChParams& p, int colour) {
  CMCSURF_DCHECK(halo_is_current(phi) && halo_is_current(nu));
  const auto& o = phi.offset();
  for_each_cell(phi, [&](int i, int j, int k) {
    if ((o[0] + i + o[1] + j + o[2] + k) % 2 == colour)
      relax_cell_ref(phi, nu, src_phi, src_nu, p, i, j, k);
  });
}

void smooth_lexicographic(Field& phi, Field& nu, const Field& src_phi, const Field& src_nu,
                          const ChParams& p) {
  // A Gauss-Seidel sweep in lexicographic order depends on the order of the blocks.
  if (!phi.whole()) throw std::logic_error("smooth_lexicographic on a block of a split grid");
  CMCSURF_DCHECK(halo_is_current(phi) && halo_is_current(nu));
  CMCSURF_CHECK(nu.size() == phi.size() && src_phi.size() == phi.size() &&
                src_nu.size() == phi.size());
  const int n = phi.n();
  const PointSolve solve{1.0 / p.dt, double(n) * n, p.epsilon * p.epsilon};
  for (int k = 0; k < phi.nz(); ++k)
    for (int j = 0; j < phi.ny(); ++j) relax_row(phi, nu, src_phi, src_nu, solve, j, k, 0, 1);
  exchange_halos(phi, nu);
}

void smooth_lexicographic_ref(Field& phi, Field& nu, const Field& src_phi, const Field& src_nu,
                              const ChParams& p) {
  if (!phi.whole()) throw std::logic_error("smooth_lexicographic_ref on a block of a split grid");
  CMCSURF_DCHECK(halo_is_current(phi) && halo_is_current(nu));
  for_each_cell(phi,
                [&](int i, int j, int k) { relax_cell_ref(phi, nu, src_phi, src_nu, p, i, j, k); });
  exchange_halos(phi, nu);
}

void ChOperator::apply(const Fields& u, Fields& out) const {
  nso_residual(u[0], u[1], nullptr, nullptr, p_, out[0], out[1]);
}

void ChOperator::residual(const Fields& u, const Fields& rhs, Fields& out) const {
  nso_residual(u[0], u[1], &rhs[0], &rhs[1], p_, out[0], out[1]);
}

void ChOperator::smooth(Fields& u, const Fields& rhs, int sweeps) const {
  // A coarsest level of odd size has no consistent red-black colouring across the periodic
  // wrap; there the lexicographic sweep is used.
  const bool red_black = p_.order == SweepOrder::kRedBlack && u[0].n() % 2 == 0;
  // A Gauss-Seidel sweep in lexicographic order depends on the order of the blocks.
  if (!red_black && u[0].decomposition())
    throw std::logic_error("lexicographic smoothing on a grid split among processes");
  for (int s = 0; s < sweeps; ++s) {
    if (!red_black) {
      smooth_lexicographic(u[0], u[1], rhs[0], rhs[1], p_);
    } else if (u[0].whole()) {  // one block: fused passes, periodic wrap per plane
      // Two sweeps per pass where the grid has room for the wavefront: the fields stream from
      // memory once for both.
      const int blocked = sweeps - s >= 2 && u[0].n() >= 8 ? 2 : 1;
      smooth_red_black_fused(u[0], u[1], rhs[0], rhs[1], p_, blocked);
      s += blocked - 1;
    } else {  // blocks of other processes: exchange after each colour
      for (int colour = 0; colour < 2; ++colour) {
        smooth_color(u[0], u[1], rhs[0], rhs[1], p_, colour);
        exchange_halos(u[0], u[1]);
      }
    }
  }
}

double ChOperator::norm(const Fields& d) const { return ch_defect_norm(d[0], d[1], p_.dt); }

void ChOperator::residual_restricted(const Fields& u, const Fields& rhs, Fields&,
                                     Fields& coarse) const {
  nso_residual_restrict(u[0], u[1], rhs[0], rhs[1], p_, coarse[0], coarse[1]);
}

double ChOperator::residual_norm(const Fields& u, const Fields& rhs, Fields&) const {
  return nso_residual_norm(u[0], u[1], rhs[0], rhs[1], p_);
}

}  // namespace cmcsurf
