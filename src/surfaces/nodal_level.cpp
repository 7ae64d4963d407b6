#include "surfaces/nodal_level.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "grid/stencil.h"
#include "measure/sharp_volume.h"
#include "surfaces/initial.h"

namespace cmcsurf {


namespace {

// Monotone map of doubles (no NaN) to unsigned integers: a < b iff key(a) < key(b).
std::uint64_t order_key(double x) {
  const auto bits = std::bit_cast<std::uint64_t>(x);
  return bits >> 63 ? ~bits : bits | (std::uint64_t(1) << 63);
}

double from_order_key(std::uint64_t key) {
  return std::bit_cast<double>(key >> 63 ? key & ~(std::uint64_t(1) << 63) : ~key);
}

// The value of 0-based order `rank` among the values of every process together: a bisection
// on the order keys, one reduced count per bit (64 passes over the local values).
double kth_value(const std::vector<double>& values, long rank, const Decomposition& d) {
  std::uint64_t lo = 0, hi = ~std::uint64_t(0);
  while (lo < hi) {
    const std::uint64_t mid = lo + (hi - lo) / 2;
    long below = 0;
    for (double v : values) below += order_key(v) <= mid;
    if (d.sum(double(below)) >= double(rank + 1))
      hi = mid;
    else
      lo = mid + 1;
  }
  return from_order_key(lo);
}

}  // namespace

namespace {

// out.f given: its level and volume fraction at alpha.
void fit_level(NodalLevelSet& out, double alpha, double tol, const Decomposition* d) {
  const bool split = d && d->distributed();
  const Field& f = out.f;
  // First guess: a fraction alpha of every 8th cell (global i, j, k even) has f > c.
  std::vector<double> values;
  values.reserve(f.interior_size() / 8 + 1);
  const auto& o = f.offset();
  for (int k = o[2] % 2; k < f.nz(); k += 2)
    for (int j = o[1] % 2; j < f.ny(); j += 2)
      for (int i = o[0] % 2; i < f.nx(); i += 2) values.push_back(f(i, j, k));
  double c0 = 0.0, f_min = 0.0, f_max = 0.0;
  if (split) {
    const long total = std::lround(d->sum(double(values.size())));
    const long above = std::clamp(std::lround(alpha * double(total)), 1L, total - 1);
    f_min = -d->max(-*std::min_element(values.begin(), values.end()));
    f_max = d->max(*std::max_element(values.begin(), values.end()));
    c0 = kth_value(values, total - above, *d);
  } else {
    const long total = long(values.size());
    const long above = std::clamp(std::lround(alpha * double(total)), 1L, total - 1);
    std::nth_element(values.begin(), values.begin() + (total - above), values.end());
    f_min = *std::min_element(values.begin(), values.end());
    f_max = *std::max_element(values.begin(), values.end());
    c0 = values[total - above];
  }
  // Secant steps on V(c) = alpha, V(c) the sharp volume fraction of {f > c}: the linear
  // interpolant of the curvature-corrected samples above c (measure/sharp_volume.h).
  Field g = Field::like(f, 1);
  curvature_corrected(f, g);
  auto volume_above = [&](double c) { return linear_volume_fraction(g, c); };
  double v0 = volume_above(c0);
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
}

NodalLevelSet nodal_field(const std::string& surface, double alpha, int n,
                          const std::shared_ptr<const Decomposition>& d, const char* who) {
  if (!is_nodal_surface(surface))
    throw std::invalid_argument(std::string(who) + ": '" + surface + "' is not a nodal surface");
  if (!(alpha > 0.0 && alpha < 1.0))
    throw std::invalid_argument(std::string(who) + ": alpha must be in (0, 1)");
  InitialFieldParams init;
  init.surface = surface;
  NodalLevelSet out;
  const bool split = d && d->distributed();
  out.f = split ? make_initial_field(init, n, 2, d) : make_initial_field(init, n, 2);
  return out;
}

}  // namespace

NodalLevelSet nodal_level_set(const std::string& surface, double alpha, int n, double tol,
                              std::shared_ptr<const Decomposition> d) {
  NodalLevelSet out = nodal_field(surface, alpha, n, d, "nodal_level_set");
  fit_level(out, alpha, tol, d.get());
  return out;
}

NodalLevelSet double_level_set(const std::string& surface, double alpha, int n, double tol,
                               std::shared_ptr<const Decomposition> d) {
  NodalLevelSet out = nodal_field(surface, alpha, n, d, "double_level_set");
  Field& f = out.f;
  for (int k = 0; k < f.nz(); ++k)
    for (int j = 0; j < f.ny(); ++j)
      for (int i = 0; i < f.nx(); ++i) f(i, j, k) = std::abs(f(i, j, k) - 0.5);
  f.exchange_halo();
  fit_level(out, alpha, tol, d.get());
  return out;
}

Field nodal_level_function(const NodalLevelSet& nodal) {
  Field psi = Field::like(nodal.f, 2);
#pragma omp parallel for schedule(static) if (psi.nx() >= kParallelMinN)
  for (int k = 0; k < psi.nz(); ++k)
    for (int j = 0; j < psi.ny(); ++j)
      for (int i = 0; i < psi.nx(); ++i) psi(i, j, k) = nodal.f(i, j, k) - nodal.level;
  psi.exchange_halo();
  return psi;
}

Field nodal_tanh_profile(const NodalLevelSet& nodal, double epsilon) {
  const Field& f = nodal.f;
  const int n = f.n();
  const double inv_width = 1.0 / (2.0 * std::numbers::sqrt2 * epsilon);
  const double inv_12h = n / 12.0;
  const std::ptrdiff_t sy = f.stride_y(), sz = f.stride_z();
  Field phi = Field::like(f, 2);
#pragma omp parallel for schedule(static) if (f.nx() >= kParallelMinN)
  for (int k = 0; k < f.nz(); ++k)
    for (int j = 0; j < f.ny(); ++j)
      for (int i = 0; i < f.nx(); ++i) {
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
