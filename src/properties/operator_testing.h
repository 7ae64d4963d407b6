// Test helpers shared by the properties operators' tests (not part of the library).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

#include "properties/voxel_operator.h"  // Vec

namespace cmcsurf::testing {

// Uniform values in [-1, 1], reproducible.
template <class Vector = properties::Vec>
Vector random_vec(std::size_t m, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vector v(m);
  for (double& x : v) x = u(rng);
  return v;
}

// Solid fractions of n^3 cells, reproducible: about a quarter 0 (fluid), a quarter 1, the rest
// between.
inline std::vector<double> random_clamped_solid(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.6, 1.6);
  std::vector<double> s(std::size_t(n) * n * n);
  for (double& v : s) v = std::clamp(u(rng), 0.0, 1.0);
  return s;
}

inline double max_abs(const properties::Vec& a) {
  double m = 0.0;
  for (double v : a) m = std::max(m, std::abs(v));
  return m;
}

}  // namespace cmcsurf::testing
