// Preconditioned conjugate gradients for a symmetric positive (semi)definite operator.
// Knows neither the operator nor the preconditioner: both are callables on raw vectors.
// Stopping rule: sqrt(r . z) <= max(relative_tolerance * sqrt(r0 . z0), absolute_tolerance),
// with z = M^-1 r (the residual's norm in the preconditioner's inverse metric), or
// max_iterations reached (converged = false, never a hang).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace cmcsurf::properties {

struct CgOptions {
  double relative_tolerance = 1e-6;
  double absolute_tolerance = 0.0;
  int max_iterations = 1000;
};

struct CgStats {
  int iterations = 0;
  double initial_norm = 0.0;       // sqrt(r0 . z0)
  double relative_residual = 0.0;  // sqrt(r . z) / sqrt(r0 . z0) (0 when r0 = 0)
  bool converged = false;
};

namespace cg_detail {
inline double dot(std::size_t m, const double* a, const double* b) {
  double s = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : s)
  for (std::size_t q = 0; q < m; ++q) s += a[q] * b[q];
  return s;
}
}  // namespace cg_detail

// Solves A x = b from x = 0. On entry r holds b; on exit x the solution and r the residual.
// p and q are scratch of size m (q also holds z = M^-1 r). apply(p, q): q = A p;
// precondition(r, z): z = M^-1 r.
template <class Apply, class Precondition>
CgStats pcg(std::size_t m, Apply&& apply, Precondition&& precondition, double* x, double* r,
            double* p, double* q, const CgOptions& o) {
  CgStats st;
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < m; ++k) x[k] = 0.0;
  precondition(r, q);
  double rz = cg_detail::dot(m, r, q);
  st.initial_norm = std::sqrt(std::max(rz, 0.0));
  const double stop = std::max(o.relative_tolerance * st.initial_norm, o.absolute_tolerance);
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < m; ++k) p[k] = q[k];
  while (true) {
    const double norm = std::sqrt(std::max(rz, 0.0));
    st.relative_residual = st.initial_norm > 0.0 ? norm / st.initial_norm : 0.0;
    if (norm <= stop) {
      st.converged = true;
      return st;
    }
    if (st.iterations >= o.max_iterations) return st;
    apply(p, q);
    const double pq = cg_detail::dot(m, p, q);
    if (!(pq > 0.0)) return st;  // breakdown: A not positive on p
    const double alpha = rz / pq;
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < m; ++k) {
      x[k] += alpha * p[k];
      r[k] -= alpha * q[k];
    }
    precondition(r, q);
    const double rz_new = cg_detail::dot(m, r, q);
    const double beta = rz_new / rz;
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < m; ++k) p[k] = q[k] + beta * p[k];
    rz = rz_new;
    ++st.iterations;
  }
}

}  // namespace cmcsurf::properties
