#include "measure/sharp_surface.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include "grid/check.h"
#include "grid/kuhn.h"
#include "multigrid/transfer.h"
#include "parallel/first_exception.h"

namespace cmcsurf {

namespace {

// |2 phi - 1| is clamped below 1 so that psi stays finite in bulk phase (|psi| <= 14.2).
constexpr double kClamp = 1.0 - 1e-12;
// Below this |grad psi|^2 (in index units) a cell has no normal; its curvature is 0.
constexpr double kFlat = 1e-24;

// Calls emit(area, centroid) for the triangles of the zero set of the Kuhn interpolant of the
// eight corner values s (psi > 0 is inside) in a unit cube; the quad of a tetrahedron cut
// two-and-two is split along one diagonal. Areas and centroids are in cube units.
template <class Emit>
inline void cube_triangles(const double s[8], Emit&& emit) {
  auto edge_point = [&](int a, int b, double p[3]) {
    const double t = s[a] / (s[a] - s[b]);
    for (int c = 0; c < 3; ++c)
      p[c] = kCubeCorner[a][c] + t * (kCubeCorner[b][c] - kCubeCorner[a][c]);
  };
  auto triangle = [&](const double* p, const double* q, const double* r) {
    const double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    const double v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    const double x = u[1] * v[2] - u[2] * v[1];
    const double y = u[2] * v[0] - u[0] * v[2];
    const double z = u[0] * v[1] - u[1] * v[0];
    const double centroid[3] = {(p[0] + q[0] + r[0]) / 3.0, (p[1] + q[1] + r[1]) / 3.0,
                                (p[2] + q[2] + r[2]) / 3.0};
    emit(0.5 * std::sqrt(x * x + y * y + z * z), centroid);
  };
  for (const auto& tet : kKuhnTets) {
    int in[4], out[4], n_in = 0, n_out = 0;
    for (int q = 0; q < 4; ++q) {
      if (s[tet[q]] > 0.0)
        in[n_in++] = tet[q];
      else
        out[n_out++] = tet[q];
    }
    if (n_in == 0 || n_out == 0) continue;
    if (n_in == 1 || n_out == 1) {
      const int apex = n_in == 1 ? in[0] : out[0];
      const int* others = n_in == 1 ? out : in;
      double a[3], b[3], c[3];
      edge_point(apex, others[0], a);
      edge_point(apex, others[1], b);
      edge_point(apex, others[2], c);
      triangle(a, b, c);
    } else {  // planar quad ac, ad, bd, bc
      double ac[3], ad[3], bd[3], bc[3];
      edge_point(in[0], out[0], ac);
      edge_point(in[0], out[1], ad);
      edge_point(in[1], out[1], bd);
      edge_point(in[1], out[0], bc);
      triangle(ac, ad, bd);
      triangle(ac, bd, bc);
    }
  }
}

// Trilinear interpolation of the corner values v at local point x in the unit cube.
inline double trilinear(const double v[8], const double x[3]) {
  double sum = 0.0;
  for (int c = 0; c < 8; ++c)
    sum += v[c] * (c & 1 ? x[0] : 1.0 - x[0]) * (c & 2 ? x[1] : 1.0 - x[1]) *
           (c & 4 ? x[2] : 1.0 - x[2]);
  return sum;
}

bool crosses(const double s[8]) {
  bool any_in = false, any_out = false;
  for (int c = 0; c < 8; ++c) (s[c] > 0.0 ? any_in : any_out) = true;
  return any_in && any_out;
}

// Central differences of psi at a cell, in index units: the gradient, the Hessian and |g|^2.
struct CellDerivatives {
  double px, py, pz, pxx, pyy, pzz, pxy, pxz, pyz, g2;
};

// f(derivatives at p), or 0 where the cell has no normal: the stencil H and K share, written
// once. Inlined, each estimator does the same operations in the same order as when each wrote
// it out (the same instructions but for registers; the same bits).
template <class F>
inline double at_cell(const double* p, std::ptrdiff_t sy, std::ptrdiff_t sz, F&& f) {
  const double c2 = 2.0 * p[0];
  const double px = 0.5 * (p[1] - p[-1]), py = 0.5 * (p[sy] - p[-sy]), pz = 0.5 * (p[sz] - p[-sz]);
  const double pxx = p[1] + p[-1] - c2, pyy = p[sy] + p[-sy] - c2, pzz = p[sz] + p[-sz] - c2;
  const double pxy = 0.25 * ((p[1 + sy] - p[1 - sy]) - (p[-1 + sy] - p[-1 - sy]));
  const double pxz = 0.25 * ((p[1 + sz] - p[1 - sz]) - (p[-1 + sz] - p[-1 - sz]));
  const double pyz = 0.25 * ((p[sy + sz] - p[sy - sz]) - (p[-sy + sz] - p[-sy - sz]));
  const double g2 = px * px + py * py + pz * pz;
  if (g2 < kFlat) return 0.0;
  return f(CellDerivatives{px, py, pz, pxx, pyy, pzz, pxy, pxz, pyz, g2});
}

struct Sums {
  double area = 0.0, area_h = 0.0, area_h2 = 0.0, area_k = 0.0, triangles = 0.0;
};

// Adds the triangles of one dual cell (corner psi s, corner H and K) to the sums and samples.
inline void add_cube(const double s[8], const double hc[8], const double kc[8], double h2,
                     Sums& sums, std::vector<CurvatureSample>* samples) {
  cube_triangles(s, [&](double a, const double* x) {
    const double hx = trilinear(hc, x);
    const double kx = trilinear(kc, x);
    a *= h2;
    sums.area += a;
    sums.area_h += a * hx;
    sums.area_h2 += a * hx * hx;
    sums.area_k += a * kx;
    sums.triangles += 1.0;
    if (samples) samples->push_back({hx, a, kx});
  });
}

LevelSetSurface finish(Sums s) {
  LevelSetSurface out;
  out.area = s.area;
  out.triangles = std::size_t(s.triangles);
  out.gaussian_curvature_integral = s.area_k;
  out.willmore_energy = s.area_h2;
  if (s.area > 0.0) {
    out.mean_curvature = s.area_h / s.area;
    const double var = s.area_h2 / s.area - out.mean_curvature * out.mean_curvature;
    out.mean_curvature_std = std::sqrt(std::max(0.0, var));
  }
  return out;
}

}  // namespace

void tanh_profile_inverse(const Field& phi, Field& psi) {
  require_ghost(psi, 2, "tanh_profile_inverse");
  if (psi.size() != phi.size() || psi.n() != phi.n())
    throw std::invalid_argument("tanh_profile_inverse: psi and phi differ in shape");
  const int nx = phi.nx(), ny = phi.ny(), nz = phi.nz();
  // The clamped bulk (phi at or beyond 0 and 1, most of a relaxed field) takes the constant
  // without calling atanh: the same values.
  const double psi_max = std::atanh(kClamp);
#pragma omp parallel for schedule(static) if (nx >= kParallelMinN)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      const double* p = &phi(0, j, k);
      double* q = &psi(0, j, k);
      for (int i = 0; i < nx; ++i) {
        const double y = 2.0 * p[i] - 1.0;
        q[i] = y >= kClamp ? psi_max : y <= -kClamp ? -psi_max : std::atanh(y);
      }
    }
  psi.exchange_halo();
}

double level_set_mean_curvature(const double* p, std::ptrdiff_t sy, std::ptrdiff_t sz,
                                double inv_h) {
  return at_cell(p, sy, sz, [inv_h](const CellDerivatives& d) {
    const double px = d.px, py = d.py, pz = d.pz;
    // div(g/|g|) = (|g|^2 Lap psi - g.Hess.g) / |g|^3
    const double num = d.pxx * (py * py + pz * pz) + d.pyy * (px * px + pz * pz) +
                       d.pzz * (px * px + py * py) -
                       2.0 * (px * py * d.pxy + px * pz * d.pxz + py * pz * d.pyz);
    return -0.5 * num / (d.g2 * std::sqrt(d.g2)) * inv_h;
  });
}

double level_set_gaussian_curvature(const double* p, std::ptrdiff_t sy, std::ptrdiff_t sz,
                                    double inv_h) {
  return at_cell(p, sy, sz, [inv_h](const CellDerivatives& d) {
    const double px = d.px, py = d.py, pz = d.pz;
    const double pxx = d.pxx, pyy = d.pyy, pzz = d.pzz, pxy = d.pxy, pxz = d.pxz, pyz = d.pyz;
    // The adjugate (cofactor matrix) of the symmetric Hessian.
    const double axx = pyy * pzz - pyz * pyz, ayy = pxx * pzz - pxz * pxz;
    const double azz = pxx * pyy - pxy * pxy, axy = pxz * pyz - pxy * pzz;
    const double axz = pxy * pyz - pxz * pyy, ayz = pxy * pxz - pxx * pyz;
    const double num = px * px * axx + py * py * ayy + pz * pz * azz +
                       2.0 * (px * py * axy + px * pz * axz + py * pz * ayz);
    return num / (d.g2 * d.g2) * inv_h * inv_h;
  });
}

LevelSetSurface level_set_surface(const Field& psi, std::vector<CurvatureSample>* samples) {
  require_ghost(psi, 2, "level_set_surface");
  CMCSURF_DCHECK(halo_is_current(psi));
  const int nx = psi.nx(), ny = psi.ny(), nz = psi.nz();
  const std::ptrdiff_t sy = psi.stride_y(), sz = psi.stride_z();
  const std::ptrdiff_t off[8] = {0, 1, sy, sy + 1, sz, sz + 1, sz + sy, sz + sy + 1};
  const double h = psi.h(), inv_h = 1.0 / h, h2 = h * h;
  std::vector<std::vector<CurvatureSample>> planes(samples ? nz : 0);
  std::vector<Sums> plane_sums(nz);
  // Dual cell (i, j, k) spans cells i..i+1, j..j+1, k..k+1 (the last one reaches the ghosts);
  // the curvature at its corners reads one more layer. A cell is a corner of up to four dual
  // cells of a plane: each thread keeps the corners' H and K of its current plane (planes k
  // and k + 1), computed on first use, so that each is computed once per plane instead of once
  // per dual cell (the same function of the same values: the same bits). Samples are appended:
  // an allocation.
  const std::size_t layer = std::size_t(nx + 1) * (ny + 1);
  FirstException errors;
#pragma omp parallel if (nx >= kParallelMinN)
  {
    std::vector<double> hcache(2 * layer), kcache(2 * layer);
    std::vector<std::uint8_t> known(2 * layer);
#pragma omp for schedule(dynamic, 1)
    for (int k = 0; k < nz; ++k)
      errors.run([&] {
        Sums sums;
        std::vector<CurvatureSample>* out = samples ? &planes[k] : nullptr;
        std::fill(known.begin(), known.end(), std::uint8_t(0));
        for (int j = 0; j < ny; ++j) {
          const double* row = &psi(0, j, k);
          for (int i = 0; i < nx; ++i) {
            const double* p = row + i;
            double s[8];
            for (int c = 0; c < 8; ++c) s[c] = p[off[c]];
            if (!crosses(s)) continue;
            double hc[8], kc[8];
            for (int c = 0; c < 8; ++c) {
              const std::size_t at = (c >> 2) * layer + std::size_t(j + (c >> 1 & 1)) * (nx + 1) +
                                     std::size_t(i + (c & 1));
              if (!known[at]) {
                hcache[at] = level_set_mean_curvature(p + off[c], sy, sz, inv_h);
                kcache[at] = level_set_gaussian_curvature(p + off[c], sy, sz, inv_h);
                known[at] = 1;
              }
              hc[c] = hcache[at];
              kc[c] = kcache[at];
            }
            add_cube(s, hc, kc, h2, sums, out);
          }
        }
        plane_sums[k] = sums;
      });
  }
  errors.rethrow();
  Sums total;  // in plane order, so the result does not depend on the thread count
  for (const Sums& s : plane_sums) {
    total.area += s.area;
    total.area_h += s.area_h;
    total.area_h2 += s.area_h2;
    total.area_k += s.area_k;
    total.triangles += s.triangles;
  }
  double reduced[5] = {total.area, total.area_h, total.area_h2, total.area_k, total.triangles};
  psi.sum_over_ranks(reduced, 5);
  if (samples) {  // in plane order, each plane copied by one thread
    std::vector<std::size_t> start(planes.size() + 1, 0);
    for (std::size_t k = 0; k < planes.size(); ++k) start[k + 1] = start[k] + planes[k].size();
    samples->resize(start.back());
#pragma omp parallel for schedule(static) if (nx >= kParallelMinN)
    for (std::size_t k = 0; k < planes.size(); ++k) {
      std::copy(planes[k].begin(), planes[k].end(), samples->begin() + std::ptrdiff_t(start[k]));
      planes[k] = {};
    }
  }
  return finish({reduced[0], reduced[1], reduced[2], reduced[3], reduced[4]});
}

LevelSetSurface level_set_surface_ref(const Field& psi, std::vector<CurvatureSample>* samples) {
  if (!psi.whole()) throw std::invalid_argument("level_set_surface_ref: needs the whole grid");
  const int n = psi.n();
  const double h = psi.h();
  auto at = [&](int i, int j, int k) {
    return psi((i % n + n) % n, (j % n + n) % n, (k % n + n) % n);
  };
  // H = -div(grad psi / |grad psi|) / 2 and K = g . adj(Hess) . g / |g|^4, written out with
  // plain central differences.
  auto curvatures_at = [&](int i, int j, int k, double& hm, double& kg) {
    const double dx = (at(i + 1, j, k) - at(i - 1, j, k)) / (2 * h);
    const double dy = (at(i, j + 1, k) - at(i, j - 1, k)) / (2 * h);
    const double dz = (at(i, j, k + 1) - at(i, j, k - 1)) / (2 * h);
    const double c = at(i, j, k);
    const double dxx = (at(i + 1, j, k) - 2 * c + at(i - 1, j, k)) / (h * h);
    const double dyy = (at(i, j + 1, k) - 2 * c + at(i, j - 1, k)) / (h * h);
    const double dzz = (at(i, j, k + 1) - 2 * c + at(i, j, k - 1)) / (h * h);
    const double dxy = (at(i + 1, j + 1, k) - at(i + 1, j - 1, k) - at(i - 1, j + 1, k) +
                        at(i - 1, j - 1, k)) / (4 * h * h);
    const double dxz = (at(i + 1, j, k + 1) - at(i + 1, j, k - 1) - at(i - 1, j, k + 1) +
                        at(i - 1, j, k - 1)) / (4 * h * h);
    const double dyz = (at(i, j + 1, k + 1) - at(i, j + 1, k - 1) - at(i, j - 1, k + 1) +
                        at(i, j - 1, k - 1)) / (4 * h * h);
    const double g2 = dx * dx + dy * dy + dz * dz;
    hm = kg = 0.0;
    if (g2 * h * h < kFlat) return;
    const double lap = dxx + dyy + dzz;
    const double hess = dx * dx * dxx + dy * dy * dyy + dz * dz * dzz +
                        2 * (dx * dy * dxy + dx * dz * dxz + dy * dz * dyz);
    hm = -0.5 * (g2 * lap - hess) / std::pow(g2, 1.5);
    // K = -det [[Hess, g], [g^T, 0]] / |g|^4, the determinant expanded along its last row.
    const double m[4][4] = {{dxx, dxy, dxz, dx}, {dxy, dyy, dyz, dy}, {dxz, dyz, dzz, dz},
                            {dx, dy, dz, 0.0}};
    double det = 0.0;
    for (int col = 0; col < 4; ++col) {
      double minor[3][3];
      for (int r = 0; r < 3; ++r)
        for (int c = 0, cc = 0; c < 4; ++c)
          if (c != col) minor[r][cc++] = m[r][c];
      const double d3 = minor[0][0] * (minor[1][1] * minor[2][2] - minor[1][2] * minor[2][1]) -
                        minor[0][1] * (minor[1][0] * minor[2][2] - minor[1][2] * minor[2][0]) +
                        minor[0][2] * (minor[1][0] * minor[2][1] - minor[1][1] * minor[2][0]);
      det += ((3 + col) % 2 ? -1.0 : 1.0) * m[3][col] * d3;
    }
    kg = -det / (g2 * g2);
  };
  Sums sums;
  if (samples) samples->clear();
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        double s[8], hc[8], kc[8];
        for (int c = 0; c < 8; ++c) {
          const int a = i + kCubeCorner[c][0], b = j + kCubeCorner[c][1], d = k + kCubeCorner[c][2];
          s[c] = at(a, b, d);
          curvatures_at(a, b, d, hc[c], kc[c]);
        }
        if (crosses(s)) add_cube(s, hc, kc, h * h, sums, samples);
      }
  return finish(sums);
}

SharpMeasures sharp_measures(const Field& phi, std::vector<CurvatureSample>* samples) {
  Field psi = Field::like(phi, 2);
  tanh_profile_inverse(phi, psi);
  return sharp_measures_psi(psi, samples);
}

namespace {
// Largest grid whose psi a decomposed run gathers for the Richardson estimate when N/2 does not
// split (32 MiB at 160^3); larger grids have blocks of at least 8 cells and never need it.
constexpr int kRichardsonGatherMaxN = 160;
}  // namespace

SharpMeasures sharp_measures_psi(const Field& psi, std::vector<CurvatureSample>* samples) {
  const Field& phi = psi;  // the same block and grid
  SharpMeasures m;
  static_cast<LevelSetSurface&>(m) = level_set_surface(psi, samples);
  m.area_error = m.mean_curvature_error = std::numeric_limits<double>::quiet_NaN();
  const int n = phi.n();
  const auto d = phi.shared_decomposition();
  const bool split = d && d->distributed();
  // On a decomposed grid psi is averaged block by block when N/2 still splits, else (blocks of
  // fewer than 8 cells: a small grid) from psi gathered on every process.
  const bool blockwise = !split || d->splits(n / 2);
  if (n % 2 == 0 && n / 2 >= 8 && (blockwise || n <= kRichardsonGatherMaxN)) {
    // Richardson: both are second order, so X_h - X = (X_2h - X_h) / 3 + O(h^3).
    Field coarse;
    if (!split) {
      coarse = Field(n / 2, 2);
      restrict_average(psi, coarse);
    } else if (blockwise) {
      coarse = Field(n / 2, 2, d);
      restrict_average(psi, coarse);
    } else {
      Field whole(n, 0);
      gather_field(psi, whole, true);
      coarse = Field(n / 2, 2);
      restrict_average(whole, coarse);
    }
    coarse.exchange_halo();
    const LevelSetSurface c = level_set_surface(coarse);
    m.area_error = std::abs(m.area - c.area) / 3.0;
    m.mean_curvature_error = std::abs(m.mean_curvature - c.mean_curvature) / 3.0;
  }
  return m;
}

}  // namespace cmcsurf
