#include "measure/sharp_volume.h"

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <vector>

#include "grid/check.h"
#include "grid/kuhn.h"
#include "grid/stencil.h"
#include "parallel/first_exception.h"

namespace cmcsurf {

namespace {

// Sum over the 6 tetrahedra of the fraction above level, for the 8 corner values.
double cube_sixfold_fraction(const double v[8], double level = 0.5) {
  double s = 0.0;
  for (const auto& t : kKuhnTets) {
    const double g[4] = {v[t[0]] - level, v[t[1]] - level, v[t[2]] - level, v[t[3]] - level};
    s += tet_fraction_above(g);
  }
  return s;
}

// cube_sixfold_fraction of the dual cell whose lower corner is *p (corner c at p[off[c]]),
// with the whole-cube cases (every corner above or none) taken without the tetrahedra.
inline double dual_cell_sixths(const double* p, const std::ptrdiff_t off[8], double level) {
  double v[8];
  double lo = p[0], hi = p[0];
  for (int c = 0; c < 8; ++c) {
    v[c] = p[off[c]];
    lo = std::min(lo, v[c]);
    hi = std::max(hi, v[c]);
  }
  return lo > level ? 6.0 : hi > level ? cube_sixfold_fraction(v, level) : 0.0;
}

}  // namespace

double tet_fraction_above(const double g[4]) {
  int pos[4], neg[4], np = 0, nn = 0;
  for (int a = 0; a < 4; ++a) {
    if (g[a] > 0.0)
      pos[np++] = a;
    else
      neg[nn++] = a;
  }
  auto t = [&](int from, int to) { return g[from] / (g[from] - g[to]); };
  switch (np) {
    case 0:
      return 0.0;
    case 4:
      return 1.0;
    case 1: {
      const int p = pos[0];
      return t(p, neg[0]) * t(p, neg[1]) * t(p, neg[2]);
    }
    case 3: {
      const int q = neg[0];
      return 1.0 - t(q, pos[0]) * t(q, pos[1]) * t(q, pos[2]);
    }
    default: {
      const double t11 = t(pos[0], neg[0]), t12 = t(pos[0], neg[1]);
      const double t21 = t(pos[1], neg[0]), t22 = t(pos[1], neg[1]);
      return t11 * t12 + t12 * t21 * (1.0 - t11) + t21 * t22 * (1.0 - t12);
    }
  }
}

double linear_volume_fraction(const Field& phi, double level) {
  require_ghost(phi, 1, "linear_volume_fraction");
  CMCSURF_DCHECK(halo_is_current(phi));
  const int nx = phi.nx(), ny = phi.ny(), nz = phi.nz();
  const std::ptrdiff_t sy = phi.stride_y(), sz = phi.stride_z();
  const std::ptrdiff_t off[8] = {0, 1, sy, sy + 1, sz, sz + 1, sz + sy, sz + sy + 1};
  double sixths = 0.0;  // sum of tetrahedron fractions: 6 per dual cell
#pragma omp parallel for schedule(static) reduction(+ : sixths)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      const double* row = &phi(0, j, k);
      for (int i = 0; i < nx; ++i) {
        sixths += dual_cell_sixths(row + i, off, level);
      }
    }
  return phi.sum_over_ranks(sixths) / (6.0 * phi.global_cells());
}

void dual_cell_fractions(const Field& phi, double level, Field& fraction) {
  require_ghost(phi, 1, "dual_cell_fractions");
  if (!phi.whole() || fraction.n() != phi.n() || !fraction.whole())
    throw std::invalid_argument("dual_cell_fractions: whole grids of one size only");
  CMCSURF_DCHECK(halo_is_current(phi));
  const int n = phi.n();
  const std::ptrdiff_t sy = phi.stride_y(), sz = phi.stride_z();
  const std::ptrdiff_t off[8] = {0, 1, sy, sy + 1, sz, sz + 1, sz + sy, sz + sy + 1};
#pragma omp parallel for schedule(static) if (n >= kParallelMinN)
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j) {
      const double* row = &phi(0, j, k);
      double* out = &fraction(0, j, k);
      for (int i = 0; i < n; ++i) {
        out[i] = dual_cell_sixths(row + i, off, level) / 6.0;
      }
    }
}

void dual_cell_fractions_ref(const Field& phi, double level, Field& fraction) {
  const int n = phi.n();
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        double v[8];
        for (int c = 0; c < 8; ++c)
          v[c] = phi((i + (c & 1)) % n, (j + (c >> 1 & 1)) % n, (k + (c >> 2 & 1)) % n);
        fraction(i, j, k) = cube_sixfold_fraction(v, level) / 6.0;
      }
}

double linear_volume_fraction_ref(const Field& phi) {
  const int n = phi.n();
  double sixths = 0.0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        double v[8];
        for (int c = 0; c < 8; ++c)
          v[c] = phi((i + (c & 1)) % n, (j + (c >> 1 & 1)) % n, (k + (c >> 2 & 1)) % n);
        sixths += cube_sixfold_fraction(v);
      }
  return sixths / (6.0 * double(phi.interior_size()));
}

void curvature_corrected(const Field& phi, Field& psi) {
  require_ghost(phi, 2, "curvature_corrected");
  CMCSURF_DCHECK(halo_is_current(phi));
  const int nx = phi.nx(), ny = phi.ny(), nz = phi.nz();
  const std::ptrdiff_t sy = phi.stride_y(), sz = phi.stride_z(), sd = 1 + sy + sz;
#pragma omp parallel for schedule(static)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      const double* p = &phi(0, j, k);
      double* q = &psi(0, j, k);
      for (int i = 0; i < nx; ++i) {
        const double c = p[i];
        const double lap = neighbour_sum(p + i, sy, sz) - 6 * c;  // h^2 Lap_d
        const double diag = p[i + sd] + p[i - sd] - 2 * c;
        q[i] = c - (lap + diag) / 24.0;
      }
    }
  psi.exchange_halo();
}

namespace {

// psi of curvature_corrected at one cell (p: phi at the cell, ghosts current).
inline double corrected_at(const double* p, std::ptrdiff_t sy, std::ptrdiff_t sz) {
  const std::ptrdiff_t sd = 1 + sy + sz;
  const double c = p[0];
  const double lap = neighbour_sum(p, sy, sz) - 6 * c;  // h^2 Lap_d
  const double diag = p[sd] + p[-sd] - 2 * c;
  return c - (lap + diag) / 24.0;
}

}  // namespace

SharpVolumeSweep::SharpVolumeSweep(const Field& phi)
    : phi_(phi),
      lower_(std::size_t(phi.nx() + 1) * (phi.ny() + 1)),
      upper_(lower_.size()),
      col_min_(std::size_t(phi.nx()) + 1),
      col_max_(col_min_.size()),
      kind_(std::size_t(phi.nx())) {
  require_ghost(phi, 2, "sharp_volume_fraction");
}

void SharpVolumeSweep::fill(std::vector<double>& q, int k) const {
  const int nx = phi_.nx(), ny = phi_.ny();
  const std::ptrdiff_t sy = phi_.stride_y(), sz = phi_.stride_z();
  for (int j = 0; j <= ny; ++j) {
    const double* p = &phi_(0, j, k);
    double* row = &q[std::size_t(j) * (nx + 1)];
    for (int i = 0; i <= nx; ++i) row[i] = corrected_at(p + i, sy, sz);
  }
}

void SharpVolumeSweep::add_plane(int k, double& sixths) {
  const int nx = phi_.nx(), ny = phi_.ny();
  if (filled_ == k) {
    std::swap(lower_, upper_);
  } else {
    fill(lower_, k);
  }
  fill(upper_, k + 1);
  filled_ = k + 1;
  const std::ptrdiff_t w = nx + 1;
  const std::ptrdiff_t off[8] = {0, 1, w, w + 1, 0, 1, w, w + 1};
  double* cmin = col_min_.data();
  double* cmax = col_max_.data();
  unsigned char* cut = kind_.data();
  for (int j = 0; j < ny; ++j) {
    const std::ptrdiff_t at0 = std::ptrdiff_t(j) * w;
    const double* l0 = lower_.data() + at0;
    const double* l1 = l0 + w;
    const double* u0 = upper_.data() + at0;
    const double* u1 = u0 + w;
    // Whether each dual cell of the row is inside (all 8 corners above 1/2: 1), cut (2) or
    // outside (0), from the extremes of its two columns of four corners: vectorised, where
    // the loop below, which adds in the cells' order, is not.
#pragma omp simd
    for (int i = 0; i <= nx; ++i) {
      cmin[i] = std::min(std::min(l0[i], l1[i]), std::min(u0[i], u1[i]));
      cmax[i] = std::max(std::max(l0[i], l1[i]), std::max(u0[i], u1[i]));
    }
    int any = 0;
#pragma omp simd reduction(| : any)
    for (int i = 0; i < nx; ++i) {
      const double lo = std::min(cmin[i], cmin[i + 1]);
      const double hi = std::max(cmax[i], cmax[i + 1]);
      const int c = lo > 0.5 ? 1 : hi > 0.5 ? 2 : 0;
      cut[i] = static_cast<unsigned char>(c);
      any |= c;
    }
    if (!any) continue;
    for (int i = 0; i < nx; ++i) {
      if (cut[i] == 1) {
        int end = i + 1;
        while (end < nx && cut[end] == 1) ++end;
        sixths = add_sixes(sixths, end - i);
        i = end - 1;
      } else if (cut[i] == 2) {
        const std::ptrdiff_t at = at0 + i;
        double v[8];
        for (int c = 0; c < 8; ++c) v[c] = (c < 4 ? lower_ : upper_)[at + off[c]];
        sixths += cube_sixfold_fraction(v);
      }
    }
  }
}

// linear_volume_fraction(curvature_corrected(phi)) without the N^3 field psi (see
// SharpVolumeSweep): same values, same per-thread order of the sums as the two passes it
// replaces; 8 bytes per cell less at the peak of a run, which calls it after every step.
double sharp_volume_fraction(const Field& phi) {
  require_ghost(phi, 2, "sharp_volume_fraction");
  CMCSURF_DCHECK(halo_is_current(phi));
  const int nz = phi.nz();
  double sixths = 0.0;  // sum of tetrahedron fractions: 6 per dual cell
  FirstException errors;
#pragma omp parallel reduction(+ : sixths)
  {
    std::optional<SharpVolumeSweep> sweep;
    const bool allocated = errors.run([&] { sweep.emplace(phi); });
#pragma omp for schedule(static)
    for (int k = 0; k < nz; ++k) {
      if (!allocated) continue;  // every thread must still reach the worksharing loop
      sweep->add_plane(k, sixths);
    }
  }
  errors.rethrow();
  return phi.sum_over_ranks(sixths) / (6.0 * phi.global_cells());
}

double sharp_volume_fraction_ref(const Field& phi) {
  const int n = phi.n();
  auto at = [&](int i, int j, int k) { return phi((i + n) % n, (j + n) % n, (k + n) % n); };
  Field psi(n, 0);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double c = at(i, j, k);
        const double lap = at(i + 1, j, k) + at(i - 1, j, k) + at(i, j + 1, k) +
                           at(i, j - 1, k) + at(i, j, k + 1) + at(i, j, k - 1) - 6 * c;
        const double diag = at(i + 1, j + 1, k + 1) + at(i - 1, j - 1, k - 1) - 2 * c;
        psi(i, j, k) = c - (lap + diag) / 24.0;
      }
  return linear_volume_fraction_ref(psi);
}

}  // namespace cmcsurf
