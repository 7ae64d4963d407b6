#include "surfaces/nodal_level.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "grid/stencil.h"
#include "measure/sharp_volume.h"
#include "surfaces/initial.h"

namespace cmcsurf {


NodalLevelSet nodal_level_set(const std::string& surface, double alpha, int n, double tol) {
  if (!is_nodal_surface(surface))
    throw std::invalid_argument("nodal_level_set: '" + surface + "' is not a nodal surface");
  if (!(alpha > 0.0 && alpha < 1.0))
    throw std::invalid_argument("nodal_level_set: alpha must be in (0, 1)");
  InitialFieldParams init;
  init.surface = surface;
  NodalLevelSet out;
  out.f = make_initial_field(init, n, 2);
  const Field& f = out.f;
  // First guess: a fraction alpha of every 8th cell (i, j, k even) has f > c.
  std::vector<double> values;
  values.reserve(f.interior_size() / 8 + 1);
  for (int k = 0; k < n; k += 2)
    for (int j = 0; j < n; j += 2)
      for (int i = 0; i < n; i += 2) values.push_back(f(i, j, k));
  const long total = long(values.size());
  const long above = std::clamp(std::lround(alpha * double(total)), 1L, total - 1);
  std::nth_element(values.begin(), values.begin() + (total - above), values.end());
  const double f_min = *std::min_element(values.begin(), values.end());
  const double f_max = *std::max_element(values.begin(), values.end());
  // Secant steps on V(c) = alpha, V(c) the sharp volume fraction of {f > c}: the linear
  // interpolant of the curvature-corrected samples above c (measure/sharp_volume.h).
  Field g = Field::like(f, 1);
  curvature_corrected(f, g);
  auto volume_above = [&](double c) { return linear_volume_fraction(g, c); };
  double c0 = values[total - above], v0 = volume_above(c0);
  values = {};
  double c1 = c0 + 1e-3 * (f_max - f_min), v1 = volume_above(c1);
  for (int it = 0; it < 30 && std::abs(v1 - alpha) > tol; ++it) {
    const double slope = (v1 - v0) / (c1 - c0);
    if (!(slope < 0.0) || !std::isfinite(slope)) break;
    const double c2 = std::clamp(c1 + (alpha - v1) / slope, f_min, f_max);
    c0 = c1;
    v0 = v1;
    c1 = c2;
    v1 = volume_above(c1);
  }
  if (std::abs(v0 - alpha) < std::abs(v1 - alpha)) {
    c1 = c0;
    v1 = v0;
  }
  out.level = c1;
  out.volume_fraction = v1;
  return out;
}

Field nodal_level_function(const NodalLevelSet& nodal) {
  Field psi = Field::like(nodal.f, 2);
  const int n = psi.n();
#pragma omp parallel for schedule(static) if (n >= kParallelMinN)
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) psi(i, j, k) = nodal.f(i, j, k) - nodal.level;
  psi.exchange_halo();
  return psi;
}

Field nodal_tanh_profile(const NodalLevelSet& nodal, double epsilon) {
  const Field& f = nodal.f;
  const int n = f.n();
  const double inv_width = 1.0 / (2.0 * std::numbers::sqrt2 * epsilon);
  const double inv_12h = n / 12.0;
  const std::ptrdiff_t sy = f.stride_y(), sz = f.stride_z();
  Field phi(n, 2);
#pragma omp parallel for schedule(static) if (n >= kParallelMinN)
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double* p = &f(i, j, k);
        const double grad = std::max(std::sqrt(grad4_sq_scaled(p, sy, sz)) * inv_12h, 1e-12);
        const double t = (p[0] - nodal.level) / grad * inv_width;
        // tanh(t) rounds to +-1 for |t| > 19.1: the bulk skips the call, same values.
        phi(i, j, k) = 0.5 * (1.0 + (std::abs(t) > 20.0 ? std::copysign(1.0, t) : std::tanh(t)));
      }
  phi.exchange_halo();
  return phi;
}

}  // namespace cmcsurf
