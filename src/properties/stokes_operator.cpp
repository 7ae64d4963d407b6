#include "properties/stokes_operator.h"

#include <algorithm>
#include <stdexcept>

#include "grid/check.h"

namespace cmcsurf::properties {

namespace {

inline std::size_t index(int n, int i, int j, int k) {
  return std::size_t(n) * (std::size_t(n) * k + j) + i;
}

// Neighbour of (i, j, k) one step along axis a (sign -1 or +1), wrapped.
inline std::size_t step(int n, int i, int j, int k, int a, int sign) {
  int v[3] = {i, j, k};
  v[a] = wrap(v[a] + sign, n);
  return index(n, v[0], v[1], v[2]);
}

// Level set of face (i, j, k) of component c: mean pore fraction of its two voxels - 1/2.
inline double face_psi(const std::vector<double>& s, int n, int c, int i, int j, int k) {
  return 0.5 - 0.5 * (s[index(n, i, j, k)] + s[step(n, i, j, k, c, -1)]);
}

// Link d of a face: axis d / 2, towards - (even d) or + (odd d).
inline int link_sign(int d) { return d & 1 ? 1 : -1; }

}  // namespace

double wall_distance(double psi_p, double psi_q) {
  const bool cut_p = psi_p < 0.5, cut_q = psi_q > -0.5;
  if (cut_p && !cut_q) return psi_p;
  if (cut_q && !cut_p) return 1.0 + psi_q;
  return psi_p / (psi_p - psi_q);
}

StokesOperator::StokesOperator(int n, const std::vector<double>& s, double viscosity,
                               double theta_min)
    : n_(n), mu_(viscosity), theta_min_(theta_min), s_(&s), diag_(3 * cells(), 0.0f),
      area_(3 * cells(), 0.0f), links_(3 * cells(), 0), active_(cells(), 0) {
  CMCSURF_CHECK(n >= 2 && s.size() == cells());
  if (!(viscosity > 0.0)) throw std::invalid_argument("viscosity must be > 0");
  if (!(theta_min > 0.0 && theta_min <= 1.0))
    throw std::invalid_argument("theta_min must lie in (0, 1]");
  for (double v : s)
    if (!(v >= 0.0 && v <= 1.0)) throw std::invalid_argument("solid fraction must lie in [0, 1]");
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const double psi = face_psi(s, n, c, i, j, k);
          if (psi <= 0.0) continue;
          const std::size_t q = index(n, i, j, k);
          double diag = 0.0, len[3] = {0.0, 0.0, 0.0};
          std::uint8_t bits = 0;
          for (int d = 0; d < 6; ++d) {
            int v[3] = {i, j, k};
            v[d / 2] = wrap(v[d / 2] + link_sign(d), n);
            const double psi_q = face_psi(s, n, c, v[0], v[1], v[2]);
            if (psi_q > 0.0) {
              diag += 1.0;
              len[d / 2] += 0.5;
              bits |= std::uint8_t(1u << d);
            } else {
              const double theta = std::max(wall_distance(psi, psi_q), theta_min);
              diag += 1.0 / theta;
              len[d / 2] += 0.5 * theta;
            }
          }
          diag_[c * cells() + q] = float(diag);
          area_[c * cells() + q] = float(len[(c + 1) % 3] * len[(c + 2) % 3]);
          links_[c * cells() + q] = bits;
          ++fluid_faces_;
          active_[q] = 1;
          active_[step(n, i, j, k, c, -1)] = 1;
        }
}

double StokesOperator::wall_theta(int c, std::size_t q, int d) const {
  if (!fluid_face(c, q) || (links_[c * cells() + q] >> d & 1)) return 0.0;
  const int n = n_, i = int(q % n), j = int(q / n % n), k = int(q / (std::size_t(n) * n));
  int v[3] = {i, j, k};
  v[d / 2] = wrap(v[d / 2] + link_sign(d), n);
  return std::max(wall_distance(face_psi(*s_, n, c, i, j, k),
                                face_psi(*s_, n, c, v[0], v[1], v[2])),
                  theta_min_);
}

double StokesOperator::face_volume(int c, std::size_t q) const {
  if (!fluid_face(c, q)) return 0.0;
  double len = 0.0;
  for (int d = 2 * c; d < 2 * c + 2; ++d)
    len += links_[c * cells() + q] >> d & 1 ? 0.5 : 0.5 * wall_theta(c, q, d);
  return face_area(c, q) * len;
}

std::size_t StokesOperator::bytes() const {
  return (diag_.size() + area_.size()) * sizeof(float) + links_.size() + active_.size();
}

namespace {

// The stencil of StokesOperator: y = K x (kAdd false) or y += K x (kAdd true); returns x . K x.
template <bool kAdd>
double stokes_stencil(int n, double mu, const float* diag, const float* area,
                      const std::uint8_t* links, const std::uint8_t* active, const double* x,
                      double* y) {
  const std::size_t m = std::size_t(n) * n * n, nn = std::size_t(n) * n;
  const double* p = x + 3 * m;
  double* yp = y + 3 * m;
  double xkx = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : xkx)
  for (int k = 0; k < n; ++k) {
    const std::size_t zm = std::size_t(wrap(k - 1, n)) * nn, z0 = std::size_t(k) * nn,
                      zp = std::size_t(wrap(k + 1, n)) * nn;
    for (int j = 0; j < n; ++j) {
      const std::size_t ym = std::size_t(wrap(j - 1, n)) * n, y0 = std::size_t(j) * n,
                        yq = std::size_t(wrap(j + 1, n)) * n;
      for (int i = 0; i < n; ++i) {
        const std::size_t im = std::size_t(wrap(i - 1, n)), ip = std::size_t(wrap(i + 1, n));
        const std::size_t q = z0 + y0 + i;
        // Neighbours in link order: -x, +x, -y, +y, -z, +z.
        const std::size_t nb[6] = {z0 + y0 + im, z0 + y0 + ip, z0 + ym + i,
                                   z0 + yq + i,  zm + y0 + i,  zp + y0 + i};
        double div = 0.0;
        for (int c = 0; c < 3; ++c) {
          const std::size_t o = c * m;
          const double* u = x + o;
          const float dq = diag[o + q];
          // Divergence of voxel q: its + face along c is face nb[2c + 1].
          const float a_up = area[o + nb[2 * c + 1]], a0 = area[o + q];
          const double up = a_up > 0.0f ? a_up * u[nb[2 * c + 1]] : 0.0;
          const double u0 = a0 > 0.0f ? a0 * u[q] : 0.0;
          div += up - u0;
          if (dq == 0.0f) {
            if (!kAdd) y[o + q] = 0.0;
            continue;
          }
          const std::uint8_t bits = links[o + q];
          double acc = double(dq) * u[q];
          for (int d = 0; d < 6; ++d)
            if (bits >> d & 1) acc -= u[nb[d]];
          const double ku = mu * acc + a0 * (p[q] - p[nb[2 * c]]);
          xkx += u[q] * ku;
          y[o + q] = kAdd ? y[o + q] + ku : ku;
        }
        const double kp = active[q] ? -div : 0.0;
        xkx += p[q] * kp;
        yp[q] = kAdd ? yp[q] + kp : kp;
      }
    }
  }
  return xkx;
}

}  // namespace

void StokesOperator::apply(const double* x, double* y) const {
  stokes_stencil<false>(n_, mu_, diag_.data(), area_.data(), links_.data(), active_.data(), x,
                        y);
}

double StokesOperator::apply_add(const double* x, double* y) const {
  return stokes_stencil<true>(n_, mu_, diag_.data(), area_.data(), links_.data(),
                              active_.data(), x, y);
}

void StokesOperator::apply_ref(const double* x, double* y) const {
  const int n = n_;
  const std::size_t m = cells();
  const std::vector<double>& s = *s_;
  auto fluid = [&](int c, int i, int j, int k) { return face_psi(s, n, c, i, j, k) > 0.0; };
  for (std::size_t q = 0; q < size(); ++q) y[q] = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const std::size_t q = index(n, i, j, k);
          if (!fluid(c, i, j, k)) continue;
          const double psi = face_psi(s, n, c, i, j, k);
          double acc = 0.0, len[3] = {0.0, 0.0, 0.0};
          for (int a = 0; a < 3; ++a)
            for (int sign : {-1, 1}) {
              int v[3] = {i, j, k};
              v[a] = wrap(v[a] + sign, n);
              if (fluid(c, v[0], v[1], v[2])) {
                acc += x[c * m + q] - x[c * m + index(n, v[0], v[1], v[2])];
                len[a] += 0.5;
              } else {
                const double theta =
                    std::max(wall_distance(psi, face_psi(s, n, c, v[0], v[1], v[2])), theta_min_);
                acc += x[c * m + q] / theta;
                len[a] += 0.5 * theta;
              }
            }
          // Gradient of p times the open area, and the face's flux into the mass balance of
          // its two voxels (B = -div).
          const double area = double(float(len[(c + 1) % 3] * len[(c + 2) % 3]));
          const std::size_t lo = step(n, i, j, k, c, -1);
          y[c * m + q] = mu_ * acc + area * (x[3 * m + q] - x[3 * m + lo]);
          y[3 * m + q] += area * x[c * m + q];
          y[3 * m + lo] -= area * x[c * m + q];
        }
}

void StokesOperator::divergence(const double* u, double* div) const {
  const int n = n_;
  const std::size_t m = cells();
#pragma omp parallel for schedule(static)
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::size_t q = index(n, i, j, k);
        double d = 0.0;
        for (int c = 0; c < 3; ++c) {
          const std::size_t up = step(n, i, j, k, c, 1);
          d += (fluid_face(c, up) ? face_area(c, up) * u[c * m + up] : 0.0) -
               (fluid_face(c, q) ? face_area(c, q) * u[c * m + q] : 0.0);
        }
        div[q] = d;
      }
}

}  // namespace cmcsurf::properties
