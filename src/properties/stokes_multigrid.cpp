#include "properties/stokes_multigrid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "grid/check.h"

namespace cmcsurf::properties {

namespace {

inline std::size_t cube(int n) { return std::size_t(n) * n * n; }

// Aggregate of cell (i, j, k) of a level of size n on the next one (ceil(n / 2) per axis).
inline std::size_t aggregate(int n, int i, int j, int k) {
  const int nc = (n + 1) / 2;
  return (std::size_t(k / 2) * nc + j / 2) * nc + i / 2;
}

// Below this size a level's loops run on one thread (the fork costs more than the work).
constexpr int kParallelN = 16;

}  // namespace

VelocityMultigrid::VelocityMultigrid(const StokesOperator& op, double sigma,
                                     VelocityMultigridOptions o)
    : op_(op), sigma_(sigma), o_(o) {
  if (!(sigma > 0.0)) throw std::invalid_argument("velocity multigrid: sigma must be > 0");
  if (o.sweeps < 1 || o.cycles < 1 || !(o.omega > 0.0 && o.omega < 1.0))
    throw std::invalid_argument("velocity multigrid: need sweeps >= 1, cycles >= 1, "
                                "0 < omega < 1");
  levels_.push_back(Level{});
  levels_[0].n = op.n();
  levels_[0].r.assign(op.cells(), 0.0);
  while (levels_.back().n > 4) coarsen(levels() - 1);
  factor_coarsest();
}

double VelocityMultigrid::diagonal(int level, int c, std::size_t q) const {
  if (level == 0) {
    const float d = op_.velocity_diagonal()[c * op_.cells() + q];
    return d > 0.0f ? double(d) + sigma_ : 0.0;
  }
  return levels_[level].diag[c * cube(levels_[level].n) + q];
}

namespace {

enum class Pass { kApply, kResidual, kSmooth };

// One pass of a level's 7-point stencil over component c: out = A x (kApply), b - A x
// (kResidual) or the damped Jacobi step x + omega (b - A x) / A_qq (kSmooth); 0 off the fluid.
// The fine level reads the operator's diagonal (plus shift) and link bits, a coarse one its
// diagonal and + link weights.
template <Pass kPass, bool kFine>
void stencil_pass(int n, const float* diag, const std::uint8_t* links, const float* wx,
                  const float* wy, const float* wz, double shift, double omega, const double* b,
                  const double* x, double* out) {
  const std::size_t nn = std::size_t(n) * n;
#pragma omp parallel for schedule(static) if (n >= kParallelN)
  for (int k = 0; k < n; ++k) {
    const std::size_t zm = std::size_t(wrap(k - 1, n)) * nn, z0 = std::size_t(k) * nn,
                      zp = std::size_t(wrap(k + 1, n)) * nn;
    for (int j = 0; j < n; ++j) {
      const std::size_t ym = std::size_t(wrap(j - 1, n)) * n, y0 = std::size_t(j) * n,
                        yq = std::size_t(wrap(j + 1, n)) * n;
      for (int i = 0; i < n; ++i) {
        const std::size_t q = z0 + y0 + i;
        const float d = diag[q];
        if (d == 0.0f) {
          out[q] = 0.0;
          continue;
        }
        const std::size_t nb[6] = {z0 + y0 + wrap(i - 1, n), z0 + y0 + wrap(i + 1, n),
                                   z0 + ym + i, z0 + yq + i, zm + y0 + i, zp + y0 + i};
        const double dd = double(d) + shift;
        double ax = dd * x[q];
        if constexpr (kFine) {
          const std::uint8_t bits = links[q];
          for (int e = 0; e < 6; ++e)
            if (bits >> e & 1) ax -= x[nb[e]];
        } else {
          ax -= double(wx[q]) * x[nb[1]] + double(wx[nb[0]]) * x[nb[0]] +
                double(wy[q]) * x[nb[3]] + double(wy[nb[2]]) * x[nb[2]] +
                double(wz[q]) * x[nb[5]] + double(wz[nb[4]]) * x[nb[4]];
        }
        if constexpr (kPass == Pass::kApply) out[q] = ax;
        if constexpr (kPass == Pass::kResidual) out[q] = b[q] - ax;
        if constexpr (kPass == Pass::kSmooth) out[q] = x[q] + omega * (b[q] - ax) / dd;
      }
    }
  }
}

}  // namespace

template <int kPass>
void VelocityMultigrid::pass(int level, int c, const double* b, const double* x,
                             double* out) const {
  constexpr Pass p = Pass(kPass);
  const Level& L = levels_[level];
  const std::size_t o = c * cube(L.n);
  if (level == 0)
    stencil_pass<p, true>(L.n, op_.velocity_diagonal().data() + o, op_.face_links().data() + o,
                          nullptr, nullptr, nullptr, sigma_, o_.omega, b, x, out);
  else
    stencil_pass<p, false>(L.n, L.diag.data() + o, nullptr, L.wx.data() + o, L.wy.data() + o,
                           L.wz.data() + o, 0.0, o_.omega, b, x, out);
}

void VelocityMultigrid::apply_level(int level, int c, const double* x, double* y) const {
  pass<int(Pass::kApply)>(level, c, nullptr, x, y);
}

void VelocityMultigrid::apply_level_ref(int level, int c, const double* x, double* y) const {
  CMCSURF_CHECK(level >= 1 && level < levels());
  const int nf = levels_[level - 1].n, n = levels_[level].n;
  std::vector<double> xf(cube(nf)), yf(cube(nf));
  for (int k = 0; k < nf; ++k)
    for (int j = 0; j < nf; ++j)
      for (int i = 0; i < nf; ++i)
        xf[(std::size_t(k) * nf + j) * nf + i] = x[aggregate(nf, i, j, k)];
  apply_level(level - 1, c, xf.data(), yf.data());
  for (std::size_t q = 0; q < cube(n); ++q) y[q] = 0.0;
  for (int k = 0; k < nf; ++k)
    for (int j = 0; j < nf; ++j)
      for (int i = 0; i < nf; ++i)
        y[aggregate(nf, i, j, k)] += 0.5 * yf[(std::size_t(k) * nf + j) * nf + i];
}

void VelocityMultigrid::coarsen(int level) {
  const int n = levels_[level].n, nc = (n + 1) / 2;
  const std::size_t m = cube(n), mc = cube(nc);
  std::vector<double> diag(3 * mc, 0.0), w[3];
  for (auto& v : w) v.assign(3 * mc, 0.0);
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const std::size_t q = (std::size_t(k) * n + j) * n + i;
          const double d = diagonal(level, c, q);
          if (d == 0.0) continue;
          const std::size_t a = aggregate(n, i, j, k);
          diag[c * mc + a] += d;
          for (int ax = 0; ax < 3; ++ax) {
            // Weight of the link to the + neighbour along ax.
            double wt;
            if (level == 0) {
              wt = op_.face_links()[c * m + q] >> (2 * ax + 1) & 1 ? 1.0 : 0.0;
            } else {
              const Level& L = levels_[level];
              wt = (ax == 0 ? L.wx : ax == 1 ? L.wy : L.wz)[c * m + q];
            }
            if (wt == 0.0) continue;
            int v[3] = {i, j, k};
            v[ax] = wrap(v[ax] + 1, n);
            if (aggregate(n, v[0], v[1], v[2]) == a)
              diag[c * mc + a] -= 2.0 * wt;  // both directions of a link inside the aggregate
            else
              w[ax][c * mc + a] += wt;
          }
        }
  Level next;
  next.n = nc;
  next.diag.resize(3 * mc);
  next.wx.resize(3 * mc);
  next.wy.resize(3 * mc);
  next.wz.resize(3 * mc);
  for (std::size_t q = 0; q < 3 * mc; ++q) {
    next.diag[q] = float(0.5 * diag[q]);
    next.wx[q] = float(0.5 * w[0][q]);
    next.wy[q] = float(0.5 * w[1][q]);
    next.wz[q] = float(0.5 * w[2][q]);
  }
  for (auto* v : {&next.b, &next.x, &next.r, &next.t, &next.e}) v->assign(mc, 0.0);
  levels_.push_back(std::move(next));
}

void VelocityMultigrid::factor_coarsest() {
  const int last = levels() - 1, n = levels_[last].n;
  const std::size_t m = cube(n);
  coarsest_.assign(3, Coarsest{});
  std::vector<double> unit(m, 0.0), col(m);
  for (int c = 0; c < 3; ++c) {
    Coarsest& cs = coarsest_[c];
    for (std::size_t q = 0; q < m; ++q)
      if (diagonal(last, c, q) > 0.0) cs.index.push_back(q);
    const std::size_t na = cs.index.size();
    std::vector<double>& a = cs.cholesky;
    a.assign(na * na, 0.0);
    for (std::size_t jj = 0; jj < na; ++jj) {
      unit[cs.index[jj]] = 1.0;
      apply_level(last, c, unit.data(), col.data());
      unit[cs.index[jj]] = 0.0;
      for (std::size_t ii = 0; ii < na; ++ii) a[ii * na + jj] = col[cs.index[ii]];
    }
    // In-place Cholesky (lower); a pivot lost to round-off gives that unknown a zero
    // correction rather than a division by zero.
    for (std::size_t jj = 0; jj < na; ++jj) {
      double d = a[jj * na + jj];
      for (std::size_t kk = 0; kk < jj; ++kk) d -= a[jj * na + kk] * a[jj * na + kk];
      const double ljj = d > 1e-14 * std::abs(a[jj * na + jj]) ? std::sqrt(d) : 0.0;
      a[jj * na + jj] = ljj;
      for (std::size_t ii = jj + 1; ii < na; ++ii) {
        double s = a[ii * na + jj];
        for (std::size_t kk = 0; kk < jj; ++kk) s -= a[ii * na + kk] * a[jj * na + kk];
        a[ii * na + jj] = ljj > 0.0 ? s / ljj : 0.0;
      }
    }
  }
}

void VelocityMultigrid::cycle(int level, int c, const double* b, double* x) const {
  const Level& L = levels_[level];
  const int n = L.n;
  const std::size_t m = cube(n);
  if (level == levels() - 1) {
    const Coarsest& cs = coarsest_[c];
    const std::size_t na = cs.index.size();
    const std::vector<double>& a = cs.cholesky;
    std::vector<double> y(na);
    for (std::size_t ii = 0; ii < na; ++ii) {
      double s = b[cs.index[ii]];
      for (std::size_t kk = 0; kk < ii; ++kk) s -= a[ii * na + kk] * y[kk];
      y[ii] = a[ii * na + ii] > 0.0 ? s / a[ii * na + ii] : 0.0;
    }
    for (std::size_t ii = na; ii-- > 0;) {
      double s = y[ii];
      for (std::size_t kk = ii + 1; kk < na; ++kk) s -= a[kk * na + ii] * y[kk];
      y[ii] = a[ii * na + ii] > 0.0 ? s / a[ii * na + ii] : 0.0;
    }
    for (std::size_t q = 0; q < m; ++q) x[q] = 0.0;
    for (std::size_t ii = 0; ii < na; ++ii) x[cs.index[ii]] = y[ii];
    return;
  }
  // The iterate alternates between x and the level's scratch (a Jacobi step cannot update in
  // place); `cur` holds it, `other` the free one.
  double *cur = x, *other = L.r.data();
  auto smooth = [&] {
    pass<int(Pass::kSmooth)>(level, c, b, cur, other);
    std::swap(cur, other);
  };
  {
    const double omega = o_.omega;
#pragma omp parallel for schedule(static) if (n >= kParallelN)
    for (std::size_t q = 0; q < m; ++q) {  // the first step from x = 0
      const double d = diagonal(level, c, q);
      x[q] = d > 0.0 ? omega * b[q] / d : 0.0;
    }
  }
  for (int s = 1; s < o_.sweeps; ++s) smooth();
  pass<int(Pass::kResidual)>(level, c, b, cur, other);
  const double* r = other;
  const Level& C = levels_[level + 1];
  const int nc = C.n;
  // Restriction (P^T): the sum over each aggregate, coarse cell by coarse cell.
#pragma omp parallel for schedule(static) if (nc >= kParallelN)
  for (int kc = 0; kc < nc; ++kc)
    for (int jc = 0; jc < nc; ++jc)
      for (int ic = 0; ic < nc; ++ic) {
        double sum = 0.0;
        for (int k = 2 * kc; k < std::min(2 * kc + 2, n); ++k)
          for (int j = 2 * jc; j < std::min(2 * jc + 2, n); ++j)
            for (int i = 2 * ic; i < std::min(2 * ic + 2, n); ++i)
              sum += r[(std::size_t(k) * n + j) * n + i];
        C.b[(std::size_t(kc) * nc + jc) * nc + ic] = sum;
      }
  cycle(level + 1, c, C.b.data(), C.x.data());
  for (int g = 1; g < o_.cycles; ++g) {
    pass<int(Pass::kResidual)>(level + 1, c, C.b.data(), C.x.data(), C.t.data());
    cycle(level + 1, c, C.t.data(), C.e.data());
    for (std::size_t q = 0; q < C.x.size(); ++q) C.x[q] += C.e[q];
  }
  // Prolongation (P): each face takes its aggregate's correction.
#pragma omp parallel for schedule(static) if (n >= kParallelN)
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::size_t q = (std::size_t(k) * n + j) * n + i;
        if (diagonal(level, c, q) > 0.0) cur[q] += C.x[aggregate(n, i, j, k)];
      }
  for (int s = 0; s < o_.sweeps; ++s) smooth();
  if (cur != x) std::copy(cur, cur + m, x);
}

void VelocityMultigrid::apply(const double* r, double* z) const {
  const std::size_t m = op_.cells();
  const double inv_mu = 1.0 / op_.viscosity();
  for (int c = 0; c < 3; ++c) {
    cycle(0, c, r + c * m, z + c * m);
#pragma omp parallel for schedule(static)
    for (std::size_t q = 0; q < m; ++q) z[c * m + q] *= inv_mu;
  }
}

std::size_t VelocityMultigrid::bytes() const {
  std::size_t b = levels_[0].r.size() * sizeof(double);
  for (int l = 1; l < levels(); ++l) {
    const Level& L = levels_[l];
    b += (L.diag.size() + L.wx.size() + L.wy.size() + L.wz.size()) * sizeof(float) +
         (L.b.size() + L.x.size() + L.r.size() + L.t.size() + L.e.size()) * sizeof(double);
  }
  for (const Coarsest& cs : coarsest_)
    b += cs.index.size() * sizeof(std::size_t) + cs.cholesky.size() * sizeof(double);
  return b;
}

}  // namespace cmcsurf::properties
