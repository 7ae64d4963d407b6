// Deterministic fields for the tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "grid/field.h"

namespace cmcsurf::testing {

inline constexpr double kPi = std::numbers::pi;

// The equilibrium tanh profile of Section 2.5 at signed distance d (> 0 in phase 1).
inline double tanh_profile(double d, double epsilon) {
  return 0.5 * (1.0 + std::tanh(d / (2.0 * std::numbers::sqrt2 * epsilon)));
}

// Uniform values in [lo, hi], reproducible, halo exchanged.
inline Field random_field(int n, int ghost, double lo, double hi, unsigned seed) {
  Field f(n, ghost);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  for_each_cell(n, [&](int i, int j, int k) { f(i, j, k) = u(rng); });
  f.exchange_halo();
  return f;
}

// Truncated gyroid nodal field of Eq. (9) (steps 1-2 of Section 4.4), halo exchanged.
inline Field gyroid_field(int n, int ghost) {
  Field f(n, ghost);
  const double h = 1.0 / n, w = 2.0 * M_PI;
  for_each_cell(n, [&](int i, int j, int k) {
    const double x = w * (i + 0.5) * h, y = w * (j + 0.5) * h, z = w * (k + 0.5) * h;
    const double v = std::sin(x) * std::cos(y) + std::sin(z) * std::cos(x) +
                     std::sin(y) * std::cos(z) + 0.5;
    f(i, j, k) = std::min(1.0, std::max(0.0, v));
  });
  f.exchange_halo();
  return f;
}

// Largest difference of the interiors (same block, any ghost widths).
// f(x, y, z) at the cell centres ((i + 1/2) h, ...) of an n^3 grid, halo exchanged.
template <class F>
Field sample_at_centres(int n, int ghost, F f) {
  Field phi(n, ghost);
  const double h = 1.0 / n;
  for_each_cell(n, [&](int i, int j, int k) {
    phi(i, j, k) = f((i + 0.5) * h, (j + 0.5) * h, (k + 0.5) * h);
  });
  phi.exchange_halo();
  return phi;
}

inline double max_abs_diff(const Field& a, const Field& b) {
  CMCSURF_CHECK(a.size() == b.size());
  double m = 0.0;
  for_each_cell(a,
                [&](int i, int j, int k) { m = std::max(m, std::abs(a(i, j, k) - b(i, j, k))); });
  return m;
}

inline double max_abs(const Field& a) {
  double m = 0.0;
  for_each_cell(a, [&](int i, int j, int k) { m = std::max(m, std::abs(a(i, j, k))); });
  return m;
}

// Plain mean of a whole field's interior (the reference for mean() in grid/field.h).
inline double mean(const Field& a) {
  CMCSURF_CHECK(a.whole());
  double s = 0.0;
  for_each_cell(a, [&](int i, int j, int k) { s += a(i, j, k); });
  return s / a.interior_size();
}

}  // namespace cmcsurf::testing
