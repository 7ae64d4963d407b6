#include "measure/measures.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "grid/check.h"
#include "grid/stencil.h"
#include "measure/sharp_volume.h"
#include "parallel/first_exception.h"

namespace cmcsurf {
namespace {

constexpr double kSixSqrt2 = 6.0 * std::numbers::sqrt2;

// Below this |sum of phi differences| around a vertex (|m| < kFlatVertex / (4h)) the vertex
// normal is set to zero instead of dividing 0 by 0. Such vertices lie in bulk phase, where the
// weight |grad_d phi|^2 is negligible anyway.
constexpr double kFlatVertex = 1e-12;

// Sum over interior cells of term(p), p pointing at the cell in phi's padded storage:
// OpenMP over k planes, unit-stride SIMD loop over i.
// The sum is over the whole grid: per-process partial sums are added over the processes.
template <class Term>
double sum_cells(const Field& phi, Term term) {
  const int nx = phi.nx(), ny = phi.ny(), nz = phi.nz();
  const std::ptrdiff_t sy = phi.stride_y(), sz = phi.stride_z();
  const double* origin = phi.data() + phi.index(0, 0, 0);
  double sum = 0.0;
#pragma omp parallel for reduction(+ : sum) schedule(static)
  for (int k = 0; k < nz; ++k) {
    double plane = 0.0;
    for (int j = 0; j < ny; ++j) {
      const double* row = origin + k * sz + j * sy;
      const Term local = term;  // a thread-local copy keeps captured strides in registers
      double s = 0.0;
#pragma omp simd reduction(+ : s)
      for (int i = 0; i < nx; ++i) s += local(row + i);
      plane += s;
    }
    sum += plane;
  }
  return phi.sum_over_ranks(sum);
}

// Three sums at once (weighted averages and spreads): term(p, &a, &b, &c) adds to a, b and c.
template <class Term>
std::array<double, 3> sum_cells3(const Field& phi, Term term) {
  const int nx = phi.nx(), ny = phi.ny(), nz = phi.nz();
  const std::ptrdiff_t sy = phi.stride_y(), sz = phi.stride_z();
  const double* origin = phi.data() + phi.index(0, 0, 0);
  double sum_a = 0.0, sum_b = 0.0, sum_c = 0.0;
#pragma omp parallel for reduction(+ : sum_a, sum_b, sum_c) schedule(static)
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      const double* row = origin + k * sz + j * sy;
      const Term local = term;  // as in sum_cells
      double a = 0.0, b = 0.0, c = 0.0;
#pragma omp simd reduction(+ : a, b, c)
      for (int i = 0; i < nx; ++i) local(row + i, a, b, c);
      sum_a += a;
      sum_b += b;
      sum_c += c;
    }
  }
  std::array<double, 3> sums = {sum_a, sum_b, sum_c};
  phi.sum_over_ranks(sums.data(), 3);
  return sums;
}

// Unit vertex normals n = m/|m| on one plane of vertices (Appendix B). Vertex (i, j, kv)
// sits at the common corner of cells i..i+1, j..j+1, kv..kv+1 (the paper's i+1/2, j+1/2,
// kv+1/2); i, j run over -1..nx-1, -1..ny-1 (block indices) and are stored at a = i+1,
// b = j+1, index b*(nx+1) + a.
struct VertexPlane {
  std::vector<double> nx, ny, nz;
  VertexPlane() = default;
  explicit VertexPlane(const Field& phi)
      : nx(std::size_t(phi.nx() + 1) * (phi.ny() + 1)), ny(nx.size()), nz(nx.size()) {}
};

void vertex_normals(const Field& phi, int kv, VertexPlane& out) {
  const int nv = phi.nx() + 1;
  const std::ptrdiff_t sy = phi.stride_y(), sz = phi.stride_z();
  for (int j = -1; j < phi.ny(); ++j) {
    const double* row = phi.data() + phi.index(-1, j, kv);
    double* nx = out.nx.data() + std::size_t(j + 1) * nv;
    double* ny = out.ny.data() + std::size_t(j + 1) * nv;
    double* nz = out.nz.data() + std::size_t(j + 1) * nv;
#pragma omp simd
    for (int a = 0; a < nv; ++a) {
      const double* p = row + a;
      const double c000 = p[0], c100 = p[1], c010 = p[sy], c110 = p[sy + 1];
      const double c001 = p[sz], c101 = p[sz + 1], c011 = p[sz + sy], c111 = p[sz + sy + 1];
      // 4h m: the four cells on the + side minus the four on the - side.
      const double mx = (c100 + c110 + c101 + c111) - (c000 + c010 + c001 + c011);
      const double my = (c010 + c110 + c011 + c111) - (c000 + c100 + c001 + c101);
      const double mz = (c001 + c101 + c011 + c111) - (c000 + c100 + c010 + c110);
      const double norm = std::sqrt(mx * mx + my * my + mz * mz);
      const double inv = norm > kFlatVertex ? 1.0 / norm : 0.0;
      nx[a] = mx * inv;
      ny[a] = my * inv;
      nz[a] = mz * inv;
    }
  }
}

}  // namespace

double mass(const Field& phi) { return mean(phi); }

double volume_fraction(const Field& phi) {
  return sum_cells(phi, [](const double* p) { return p[0] > 0.5 ? 1.0 : 0.0; }) /
         phi.global_cells();
}

double l2_norm(const Field& a) {
  return std::sqrt(sum_cells(a, [](const double* p) { return p[0] * p[0]; }) /
                   a.global_cells());
}

double l2_diff(const Field& a, const Field& b) {
  if (a.n() != b.n() || a.size() != b.size())
    throw std::invalid_argument("l2_diff: fields of different size");
  const int nx = a.nx(), ny = a.ny(), nz = a.nz();
  double sum = 0.0;
#pragma omp parallel for reduction(+ : sum) schedule(static)
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      const double* pa = &a(0, j, k);
      const double* pb = &b(0, j, k);
      double s = 0.0;
#pragma omp simd reduction(+ : s)
      for (int i = 0; i < nx; ++i) s += (pa[i] - pb[i]) * (pa[i] - pb[i]);
      sum += s;
    }
  }
  return std::sqrt(a.sum_over_ranks(sum) / a.global_cells());
}

// Section 2.2: F = 6 sqrt2 sum [W/eps + eps/2 |grad_h phi|^2] h^3, forward face differences.
double energy(const Field& phi, double epsilon) {
  require_ghost(phi, 1, "energy");
  CMCSURF_DCHECK(halo_is_current(phi));
  const std::ptrdiff_t sy = phi.stride_y(), sz = phi.stride_z();
  const double h = phi.h();
  const double c_grad = 0.5 * epsilon / (h * h);
  const double inv_eps = 1.0 / epsilon;
  const double sum = sum_cells(phi, [=](const double* p) {
    const double dx = p[1] - p[0], dy = p[sy] - p[0], dz = p[sz] - p[0];
    return double_well(p[0]) * inv_eps + c_grad * (dx * dx + dy * dy + dz * dz);
  });
  return kSixSqrt2 * sum * h * h * h;
}

// Appendix B: A = sum 6 sqrt2 eps |grad_d phi|^2 h^3.
double area(const Field& phi, double epsilon) {
  require_ghost(phi, 2, "area");
  CMCSURF_DCHECK(halo_is_current(phi));
  const std::ptrdiff_t sy = phi.stride_y(), sz = phi.stride_z();
  const double h = phi.h();
  const double sum = sum_cells(phi, [=](const double* p) { return grad4_sq_scaled(p, sy, sz); });
  return kSixSqrt2 * epsilon * sum / (144.0 * h * h) * h * h * h;
}

// |grad_d phi|^2 with the fourth-order central gradient of Appendix B, written out plainly
// for the reference twins.
static double grad4_squared_ref(const Field& phi, int i, int j, int k) {
  const double h = phi.h();
        const double gx = (phi(i - 2, j, k) - 8.0 * phi(i - 1, j, k) + 8.0 * phi(i + 1, j, k) -
                           phi(i + 2, j, k)) /
                          (12.0 * h);
        const double gy = (phi(i, j - 2, k) - 8.0 * phi(i, j - 1, k) + 8.0 * phi(i, j + 1, k) -
                           phi(i, j + 2, k)) /
                          (12.0 * h);
        const double gz = (phi(i, j, k - 2) - 8.0 * phi(i, j, k - 1) + 8.0 * phi(i, j, k + 1) -
                           phi(i, j, k + 2)) /
                          (12.0 * h);
  return gx * gx + gy * gy + gz * gz;
}

double area_ref(const Field& phi, double epsilon) {
  require_ghost(phi, 2, "area_ref");
  const double h = phi.h();
  double sum = 0.0;
  for_each_cell(phi, [&](int i, int j, int k) {
    sum += 6.0 * std::sqrt(2.0) * epsilon * grad4_squared_ref(phi, i, j, k) * h * h * h;
  });
  return phi.sum_over_ranks(sum);
}

// Appendix B: kappa = div_d(m/|m|) at cell centres from the 8 vertex normals of each cell,
// H = -1/2 sum(kappa w) / sum(w), w = |grad_d phi|^2. Each thread sweeps a contiguous block of
// k planes, keeping the vertex planes below and above the current cell plane.
double mean_curvature(const Field& phi) {
  require_ghost(phi, 2, "mean_curvature");
  CMCSURF_DCHECK(halo_is_current(phi));
  const int nx = phi.nx(), ny = phi.ny(), nz = phi.nz(), nv = nx + 1;
  const std::ptrdiff_t sy = phi.stride_y(), sz = phi.stride_z();
  const double h = phi.h();
  double sum_kw = 0.0, sum_w = 0.0;
  FirstException errors;
#pragma omp parallel reduction(+ : sum_kw, sum_w)
  {
    VertexPlane below, above;
    const bool allocated = errors.run([&] { below = above = VertexPlane(phi); });
    int last_k = -2;
#pragma omp for schedule(static)
    for (int k = 0; k < nz; ++k) {
      if (!allocated) continue;  // every thread must still reach the worksharing loop
      if (last_k == k - 1) {
        std::swap(below, above);
      } else {
        vertex_normals(phi, k - 1, below);
      }
      vertex_normals(phi, k, above);
      last_k = k;
      for (int j = 0; j < ny; ++j) {
        const double* row = phi.data() + phi.index(0, j, k);
        // Vertex (i-1, j-1) of a plane is at a = i, b = j; (i, j) at a = i+1, b = j+1.
        const std::size_t lo = std::size_t(j) * nv, hi = std::size_t(j + 1) * nv;
        const double* bx = below.nx.data();
        const double* by = below.ny.data();
        const double* bz = below.nz.data();
        const double* ax = above.nx.data();
        const double* ay = above.ny.data();
        const double* az = above.nz.data();
        double s_kw = 0.0, s_w = 0.0;
#pragma omp simd reduction(+ : s_kw, s_w)
        for (int i = 0; i < nx; ++i) {
          const std::size_t l0 = lo + i, l1 = lo + i + 1, h0 = hi + i, h1 = hi + i + 1;
          const double div_x =
              (bx[l1] + bx[h1] + ax[l1] + ax[h1]) - (bx[l0] + bx[h0] + ax[l0] + ax[h0]);
          const double div_y =
              (by[h0] + by[h1] + ay[h0] + ay[h1]) - (by[l0] + by[l1] + ay[l0] + ay[l1]);
          const double div_z =
              (az[l0] + az[l1] + az[h0] + az[h1]) - (bz[l0] + bz[l1] + bz[h0] + bz[h1]);
          const double w = grad4_sq_scaled(row + i, sy, sz);
          s_kw += (div_x + div_y + div_z) * w;
          s_w += w;
        }
        sum_kw += s_kw;
        sum_w += s_w;
      }
    }
  }
  errors.rethrow();
  double sums[2] = {sum_kw, sum_w};
  phi.sum_over_ranks(sums, 2);
  if (sums[1] == 0.0) return 0.0;  // constant field: no interface
  return -0.5 * (sums[0] / (4.0 * h)) / sums[1];
}

double mean_curvature_ref(const Field& phi) {
  require_ghost(phi, 2, "mean_curvature_ref");
  const int n = phi.n();
  const double h = phi.h();
  // Unit normal at the vertex shared by cells i..i+1, j..j+1, k..k+1.
  auto normal = [&](int i, int j, int k, double n_out[3]) {
    double m[3] = {0.0, 0.0, 0.0};
    for (int c = 0; c <= 1; ++c)
      for (int b = 0; b <= 1; ++b)
        for (int a = 0; a <= 1; ++a) {
          const double v = phi(i + a, j + b, k + c) / (4.0 * h);
          m[0] += a ? v : -v;
          m[1] += b ? v : -v;
          m[2] += c ? v : -v;
        }
    const double norm = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    for (int d = 0; d < 3; ++d) n_out[d] = norm * 4.0 * h > kFlatVertex ? m[d] / norm : 0.0;
  };
  double sum_kw = 0.0, sum_w = 0.0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        double kappa = 0.0;
        for (int c = 0; c <= 1; ++c)
          for (int b = 0; b <= 1; ++b)
            for (int a = 0; a <= 1; ++a) {
              double nv[3];
              normal(i - 1 + a, j - 1 + b, k - 1 + c, nv);
              kappa +=
                  ((a ? nv[0] : -nv[0]) + (b ? nv[1] : -nv[1]) + (c ? nv[2] : -nv[2])) / (4.0 * h);
            }
        const double w = grad4_squared_ref(phi, i, j, k);
        sum_kw += kappa * w;
        sum_w += w;
      }
  if (sum_w == 0.0) return 0.0;
  return -0.5 * sum_kw / sum_w;
}

// Section 2.5 with mu = 6 sqrt2 nu / eps and the Gibbs-Thomson factor H = mu/2 = 3 sqrt2 nu / eps
// (not the paper's mu/3, see measures.h), averaged with weight |grad_d phi|^2,
// nu = W'(phi) - eps^2 Lap_d phi (7-point Laplacian of Section 3).
namespace {

// The sums of nu |grad_d phi|^2 and |grad_d phi|^2 over the cells: the weighted mean of nu that
// mean_curvature_mu reports and equilibrium_residual measures the spread around, and the
// spread's sum about `shift`.
WeightedNuSums weighted_nu_sums(const Field& phi, double epsilon, double shift = 0.0) {
  CMCSURF_DCHECK(halo_is_current(phi));
  const std::ptrdiff_t sy = phi.stride_y(), sz = phi.stride_z();
  const double h = phi.h();
  const double inv_h2 = 1.0 / (h * h);
  const double eps2 = epsilon * epsilon;
  const auto [nu_w, w, shifted_w] =
      sum_cells3(phi, [=](const double* p, double& nw, double& sw, double& dw) {
        const double nu = double_well_prime(p[0]) - eps2 * laplacian(p, sy, sz, inv_h2);
        const double g = grad4_sq_scaled(p, sy, sz);
        nw += nu * g;
        sw += g;
        const double d = nu - shift;
        dw += d * d * g;
      });
  return WeightedNuSums{nu_w, w, shift, shifted_w};
}

}  // namespace

double mean_curvature_mu(const Field& phi, double epsilon) {
  require_ghost(phi, 2, "mean_curvature_mu");
  const WeightedNuSums sums = weighted_nu_sums(phi, epsilon);
  if (sums.w == 0.0) return 0.0;
  return 3.0 * std::numbers::sqrt2 / epsilon * sums.nu_w / sums.w;  // H = mu/2
}

double mean_curvature_mu_ref(const Field& phi, double epsilon) {
  require_ghost(phi, 2, "mean_curvature_mu_ref");
  const double h = phi.h();
  double sum_nw = 0.0, sum_w = 0.0;
  for_each_cell(phi, [&](int i, int j, int k) {
    const double lap = (phi(i + 1, j, k) + phi(i - 1, j, k) + phi(i, j + 1, k) + phi(i, j - 1, k) +
                        phi(i, j, k + 1) + phi(i, j, k - 1) - 6.0 * phi(i, j, k)) /
                       (h * h);
    const double v = phi(i, j, k);
    const double nu = (v * v * v - 1.5 * v * v + 0.5 * v) - epsilon * epsilon * lap;
    const double w = grad4_squared_ref(phi, i, j, k);
    sum_nw += nu * w;
    sum_w += w;
  });
  double sums[2] = {sum_nw, sum_w};
  phi.sum_over_ranks(sums, 2);
  if (sums[1] == 0.0) return 0.0;
  return 3.0 * std::sqrt(2.0) / epsilon * sums[0] / sums[1];
}

double equilibrium_residual(const Field& phi, double epsilon) {
  require_ghost(phi, 2, "equilibrium_residual");
  // Two passes, the mean first: the spread is small beside nu itself.
  return equilibrium_residual(phi, epsilon, weighted_nu_sums(phi, epsilon));
}

double equilibrium_residual_one_pass(const WeightedNuSums& sums, double epsilon) {
  if (sums.w == 0.0) return 0.0;
  const double offset = sums.nu_w / sums.w - sums.shift;  // mean - shift
  const double variance = sums.shifted_w / sums.w - offset * offset;
  if (!(offset * offset <= variance)) return -1.0;
  return 3.0 * std::numbers::sqrt2 / epsilon * std::sqrt(variance);
}

bool equilibrium_met(const Field& phi, double epsilon, const WeightedNuSums& sums, double tol) {
  const double r = equilibrium_residual_one_pass(sums, epsilon);
  if (r >= 0.0 && std::abs(r - tol) > kOnePassMargin * tol) return r <= tol;
  return equilibrium_residual(phi, epsilon, sums) <= tol;
}

double equilibrium_residual(const Field& phi, double epsilon, const WeightedNuSums& sums) {
  require_ghost(phi, 2, "equilibrium_residual");
  CMCSURF_DCHECK(halo_is_current(phi));
  const std::ptrdiff_t sy = phi.stride_y(), sz = phi.stride_z();
  const double h = phi.h();
  const double inv_h2 = 1.0 / (h * h);
  const double eps2 = epsilon * epsilon;
  const double sum_w = sums.w;
  if (sum_w == 0.0) return 0.0;
  const double mean_nu = sums.nu_w / sum_w;
  const double sum_dw = sum_cells(phi, [=](const double* p) {
    const double d = double_well_prime(p[0]) - eps2 * laplacian(p, sy, sz, inv_h2) - mean_nu;
    return d * d * grad4_sq_scaled(p, sy, sz);
  });
  return 3.0 * std::numbers::sqrt2 / epsilon * std::sqrt(std::max(0.0, sum_dw / sum_w));
}

double equilibrium_residual_ref(const Field& phi, double epsilon) {
  require_ghost(phi, 2, "equilibrium_residual_ref");
  const double h = phi.h();
  auto nu_at = [&](int i, int j, int k) {
    const double lap = (phi(i + 1, j, k) + phi(i - 1, j, k) + phi(i, j + 1, k) + phi(i, j - 1, k) +
                        phi(i, j, k + 1) + phi(i, j, k - 1) - 6.0 * phi(i, j, k)) /
                       (h * h);
    const double v = phi(i, j, k);
    return (v * v * v - 1.5 * v * v + 0.5 * v) - epsilon * epsilon * lap;
  };
  double sums[3] = {0.0, 0.0, 0.0};  // w nu, w, w (nu - mean)^2
  for_each_cell(phi, [&](int i, int j, int k) {
    const double w = grad4_squared_ref(phi, i, j, k);
    sums[0] += nu_at(i, j, k) * w;
    sums[1] += w;
  });
  phi.sum_over_ranks(sums, 2);
  if (sums[1] == 0.0) return 0.0;
  const double mean_nu = sums[0] / sums[1];
  for_each_cell(phi, [&](int i, int j, int k) {
    const double d = nu_at(i, j, k) - mean_nu;
    sums[2] += d * d * grad4_squared_ref(phi, i, j, k);
  });
  phi.sum_over_ranks(&sums[2], 1);
  return 3.0 * std::sqrt(2.0) / epsilon * std::sqrt(sums[2] / sums[1]);
}

double energy_ref(const Field& phi, double epsilon) {
  require_ghost(phi, 1, "energy_ref");
  const double h = phi.h();
  double sum = 0.0;
  for_each_cell(phi, [&](int i, int j, int k) {
    const double v = phi(i, j, k);
    const double dx = (phi(i + 1, j, k) - v) / h, dy = (phi(i, j + 1, k) - v) / h,
                 dz = (phi(i, j, k + 1) - v) / h;
    const double w = 0.25 * v * v * (1.0 - v) * (1.0 - v);
    sum += 6.0 * std::sqrt(2.0) * (w / epsilon + 0.5 * epsilon * (dx * dx + dy * dy + dz * dz)) *
           h * h * h;
  });
  return phi.sum_over_ranks(sum);
}

// One pass for the history (see measures.h). Each quantity has its own inner loop over the
// row, written as its function's, so that it vectorises and adds in the same order; the rows
// come from the cache after the first; the sharp volume fraction's sweep adds each plane as
// its own function does. area and energy add rows into a plane sum as sum_cells
// does, l2_diff and weighted_nu_sums add rows straight into the thread's sum, and mass (mean)
// runs serially below kParallelMinN: its plane sums are then added in order after the loop.
StepMeasures step_measures(const Field& phi, const Field& before, double epsilon, bool nu_sums,
                           double nu_shift) {
  require_ghost(phi, 2, "step_measures");
  CMCSURF_DCHECK(halo_is_current(phi));
  if (before.n() != phi.n() || before.size() != phi.size())
    throw std::invalid_argument("step_measures: fields of different size");
  const int nx = phi.nx(), ny = phi.ny(), nz = phi.nz();
  const std::ptrdiff_t sy = phi.stride_y(), sz = phi.stride_z();
  const double h = phi.h();
  const double c_grad = 0.5 * epsilon / (h * h);
  const double inv_eps = 1.0 / epsilon;
  const double inv_h2 = 1.0 / (h * h);
  const double eps2 = epsilon * epsilon;
  const bool mass_parallel = nx >= kParallelMinN;
  std::vector<double> mass_planes(mass_parallel ? 0 : nz);
  double s_area = 0.0, s_energy = 0.0, s_mass = 0.0, s_diff = 0.0, s_nw = 0.0, s_w = 0.0;
  double s_sixths = 0.0, s_dw = 0.0;
  FirstException errors;
#pragma omp parallel reduction(+ : s_area, s_energy, s_mass, s_diff, s_nw, s_w, s_sixths, s_dw)
  {
    std::optional<SharpVolumeSweep> sweep;  // the sharp volume fraction's planes (a thread's)
    const bool allocated = errors.run([&] { sweep.emplace(phi); });
#pragma omp for schedule(static)
    for (int k = 0; k < nz; ++k) {
      if (!allocated) continue;  // every thread must still reach the worksharing loop
      double plane_area = 0.0, plane_energy = 0.0, plane_mass = 0.0;
      for (int j = 0; j < ny; ++j) {
        const double* row = &phi(0, j, k);
        const double* old_row = &before(0, j, k);
        double a = 0.0, e = 0.0, m = 0.0, d = 0.0;
#pragma omp simd reduction(+ : a)
        for (int i = 0; i < nx; ++i) a += grad4_sq_scaled(row + i, sy, sz);
#pragma omp simd reduction(+ : e)
        for (int i = 0; i < nx; ++i) {
          const double* p = row + i;
          const double dx = p[1] - p[0], dy = p[sy] - p[0], dz = p[sz] - p[0];
          e += double_well(p[0]) * inv_eps + c_grad * (dx * dx + dy * dy + dz * dz);
        }
#pragma omp simd reduction(+ : m)
        for (int i = 0; i < nx; ++i) m += row[i];
#pragma omp simd reduction(+ : d)
        for (int i = 0; i < nx; ++i) d += (row[i] - old_row[i]) * (row[i] - old_row[i]);
        plane_area += a;
        plane_energy += e;
        plane_mass += m;
        s_diff += d;
        if (nu_sums) {
          double nw = 0.0, w = 0.0, dw = 0.0;
#pragma omp simd reduction(+ : nw, w, dw)
          for (int i = 0; i < nx; ++i) {
            const double* p = row + i;
            const double nu = double_well_prime(p[0]) - eps2 * laplacian(p, sy, sz, inv_h2);
            const double g = grad4_sq_scaled(p, sy, sz);
            nw += nu * g;
            w += g;
            const double dn = nu - nu_shift;
            dw += dn * dn * g;
          }
          s_nw += nw;
          s_w += w;
          s_dw += dw;
        }
      }
      s_area += plane_area;
      s_energy += plane_energy;
      if (mass_parallel)
        s_mass += plane_mass;
      else
        mass_planes[std::size_t(k)] = plane_mass;
      sweep->add_plane(k, s_sixths);
    }
  }
  errors.rethrow();
  for (const double m : mass_planes) s_mass += m;
  double sums[8] = {s_area, s_energy, s_mass, s_diff, s_nw, s_w, s_sixths, s_dw};
  phi.sum_over_ranks(sums, 8);
  StepMeasures r;
  r.area = kSixSqrt2 * epsilon * sums[0] / (144.0 * h * h) * h * h * h;
  r.energy = kSixSqrt2 * sums[1] * h * h * h;
  r.mass = sums[2] / phi.global_cells();
  r.d_phi = std::sqrt(sums[3] / phi.global_cells());
  if (nu_sums) r.nu_sums = WeightedNuSums{sums[4], sums[5], nu_shift, sums[7]};
  r.volume_fraction = sums[6] / (6.0 * phi.global_cells());
  return r;
}

StepMeasures step_measures_ref(const Field& phi, const Field& before, double epsilon,
                               bool nu_sums, double nu_shift) {
  StepMeasures r;
  r.area = area(phi, epsilon);
  r.energy = energy(phi, epsilon);
  r.mass = mass(phi);
  r.d_phi = l2_diff(phi, before);
  r.volume_fraction = sharp_volume_fraction(phi);
  if (nu_sums) r.nu_sums = weighted_nu_sums(phi, epsilon, nu_shift);
  return r;
}

}  // namespace cmcsurf
