// Preconditioned MINRES for a symmetric (indefinite, possibly singular but consistent)
// operator with a symmetric positive (semi)definite preconditioner M (Elman, Silvester and
// Wathen, Finite Elements and Fast Iterative Solvers, Algorithm 4.1). Knows neither the
// operator nor the preconditioner: both are callables on raw vectors, as in pcg.h.
// Stopping rule: the residual's norm in the M^-1 metric, |eta| (exact in exact arithmetic),
// <= max(relative_tolerance * its initial value, absolute_tolerance), or max_iterations
// reached (converged = false, never a hang).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>

#include "properties/pcg.h"  // CgOptions, CgStats, cg_detail::dot

namespace cmcsurf::properties {

// The five scratch vectors MINRES keeps besides x, each of size m.
struct MinresWork {
  double *v_prev, *v, *z, *w_prev, *w;
};

// Solves K x = b from x = 0; on entry wk.v holds b. apply_add(a, y): y += K a, returning
// a . K a (so no vector holds K a alone); precondition(r, z): z = M^-1 r.
template <class ApplyAdd, class Precondition>
CgStats minres(std::size_t m, ApplyAdd&& apply_add, Precondition&& precondition, double* x,
               MinresWork wk, const CgOptions& o) {
  using cg_detail::dot;
  CgStats st;
  double *v_prev = wk.v_prev, *v = wk.v, *z = wk.z, *w_prev = wk.w_prev, *w = wk.w;
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < m; ++k) {
    x[k] = 0.0;
    v_prev[k] = 0.0;
    w_prev[k] = 0.0;
    w[k] = 0.0;
  }
  precondition(v, z);
  double gamma = std::sqrt(std::max(dot(m, z, v), 0.0)), gamma_prev = 1.0;
  st.initial_norm = gamma;
  const double stop = std::max(o.relative_tolerance * gamma, o.absolute_tolerance);
  double eta = gamma, s_prev = 0.0, s = 0.0, c_prev = 1.0, c = 1.0;
  while (true) {
    st.relative_residual = st.initial_norm > 0.0 ? std::abs(eta) / st.initial_norm : 0.0;
    if (std::abs(eta) <= stop) {
      st.converged = true;
      return st;
    }
    if (st.iterations >= o.max_iterations || !(gamma > 0.0)) return st;
    // Lanczos: v_{j+1} = K z_j - (delta / gamma) v_j - (gamma / gamma_prev) v_{j-1}, built in
    // place of v_{j-1}.
    const double inv_gamma = 1.0 / gamma, bb = gamma / gamma_prev;
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < m; ++k) {
      z[k] *= inv_gamma;
      v_prev[k] *= -bb;
    }
    const double delta = apply_add(z, v_prev);
    const double a = delta / gamma;
    // The rotations' a2, a3 do not need the next gamma, so w_prev takes z - a3 w_prev - a2 w
    // now and z is free for the next z.
    const double a2 = s * delta + c_prev * c * gamma, a3 = s_prev * gamma;
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < m; ++k) {
      v_prev[k] -= a * v[k];
      w_prev[k] = z[k] - a3 * w_prev[k] - a2 * w[k];
    }
    std::swap(v_prev, v);  // v: v_{j+1}, v_prev: v_j
    precondition(v, z);
    const double gamma_next = std::sqrt(std::max(dot(m, z, v), 0.0));
    const double a0 = c * delta - c_prev * s * gamma;
    const double a1 = std::sqrt(a0 * a0 + gamma_next * gamma_next);
    if (!(a1 > 0.0)) return st;  // breakdown
    const double c_next = a0 / a1, s_next = gamma_next / a1;
    // The next search direction (in w_prev's place) and the update of x.
    const double inv_a1 = 1.0 / a1, step = c_next * eta;
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < m; ++k) {
      w_prev[k] *= inv_a1;
      x[k] += step * w_prev[k];
    }
    std::swap(w_prev, w);
    eta = -s_next * eta;
    gamma_prev = gamma;
    gamma = gamma_next;
    c_prev = c;
    c = c_next;
    s_prev = s;
    s = s_next;
    ++st.iterations;
  }
}

}  // namespace cmcsurf::properties
