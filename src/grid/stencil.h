// Shared stencil helpers on padded storage (x unit stride, sy, sz strides).
#pragma once

#include <cstddef>

namespace cmcsurf {

// Sum of the six face neighbours of p[0].
inline double neighbour_sum(const double* p, std::ptrdiff_t sy, std::ptrdiff_t sz) {
  return (p[-1] + p[1]) + (p[-sy] + p[sy]) + (p[-sz] + p[sz]);
}

// 7-point Laplacian Delta_d of Section 3.
inline double laplacian(const double* p, std::ptrdiff_t sy, std::ptrdiff_t sz, double inv_h2) {
  return (neighbour_sum(p, sy, sz) - 6.0 * p[0]) * inv_h2;
}

// 12h times the fourth-order central difference of Appendix B along stride s.
inline double diff4_scaled(const double* p, std::ptrdiff_t s) {
  return (p[-2 * s] - p[2 * s]) + 8.0 * (p[s] - p[-s]);
}

// (12h)^2 |grad_d phi|^2 at p with the fourth-order gradient of Appendix B.
inline double grad4_sq_scaled(const double* p, std::ptrdiff_t sy, std::ptrdiff_t sz) {
  const double gx = diff4_scaled(p, 1), gy = diff4_scaled(p, sy), gz = diff4_scaled(p, sz);
  return gx * gx + gy * gy + gz * gz;
}

}  // namespace cmcsurf
