#include "properties/solid_fraction.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "measure/sharp_volume.h"

namespace cmcsurf::properties {

std::vector<double> solid_fraction_from_phi(const Field& phi, double level) {
  if (!phi.whole() || phi.ghost() < 1)
    throw std::invalid_argument("solid_fraction_from_phi: needs a whole grid with ghosts");
  Field fraction(phi.n(), 0);
  dual_cell_fractions(phi, level, fraction);  // measure/sharp_volume.h: the cubes one by one
  return voxel_values(fraction);
}

std::vector<double> voxel_values(const Field& fraction) {
  const int n = fraction.n();
  std::vector<double> s(std::size_t(n) * n * n);
  for_each_cell(fraction, [&](int i, int j, int k) {
    s[(std::size_t(k) * n + j) * n + i] = std::clamp(fraction(i, j, k), 0.0, 1.0);
  });
  return s;
}

std::vector<double> nodal_gyroid_solid_fraction(int n, GyroidSolid kind, double porosity) {
  if (n < 2 || !(porosity > 0.0 && porosity < 1.0))
    throw std::invalid_argument("gyroid: need n >= 2 and porosity in (0, 1)");
  const std::size_t cells = std::size_t(n) * n * n;
  std::vector<double> f(cells), grad(cells), s(cells);
  const double w = 2.0 * M_PI, h = 1.0 / n;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x = w * (i + 0.5) * h, y = w * (j + 0.5) * h, z = w * (k + 0.5) * h;
        const std::size_t e = (std::size_t(k) * n + j) * n + i;
        f[e] = std::sin(x) * std::cos(y) + std::sin(y) * std::cos(z) + std::sin(z) * std::cos(x);
        const double gx = std::cos(x) * std::cos(y) - std::sin(z) * std::sin(x);
        const double gy = -std::sin(x) * std::sin(y) + std::cos(y) * std::cos(z);
        const double gz = -std::sin(y) * std::sin(z) + std::cos(z) * std::cos(x);
        grad[e] = std::max(w * std::sqrt(gx * gx + gy * gy + gz * gz), 1e-12);  // per unit X
      }
  auto fill = [&](double c) {
    double sum = 0.0;
    for (std::size_t e = 0; e < cells; ++e) {
      const double d = kind == GyroidSolid::network ? (f[e] - c) / grad[e]
                                                    : (c - std::abs(f[e])) / grad[e];
      s[e] = std::clamp(0.5 + d / h, 0.0, 1.0);
      sum += s[e];
    }
    return sum / double(cells);
  };
  // Solid fraction decreases with c (network) and increases with c (sheet).
  double lo = kind == GyroidSolid::network ? -1.5 : 0.0, hi = 1.5;
  const double target = 1.0 - porosity;
  for (int it = 0; it < 100; ++it) {
    const double c = 0.5 * (lo + hi);
    const double v = fill(c);
    if ((v > target) == (kind == GyroidSolid::network))
      lo = c;
    else
      hi = c;
  }
  fill(0.5 * (lo + hi));
  return s;
}

std::vector<double> restrict_solid_fraction(int n, const std::vector<double>& s) {
  if (n < 4 || n % 2 != 0 || s.size() != std::size_t(n) * n * n)
    throw std::invalid_argument("restrict_solid_fraction: need an even n >= 4 and n^3 values");
  const int m = n / 2;
  std::vector<double> c(std::size_t(m) * m * m, 0.0);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        c[(std::size_t(k / 2) * m + j / 2) * m + i / 2] +=
            0.125 * s[(std::size_t(k) * n + j) * n + i];
  return c;
}

}  // namespace cmcsurf::properties
