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

}  // namespace cmcsurf
