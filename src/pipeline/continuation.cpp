#include "pipeline/continuation.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "measure/measures.h"

namespace cmcsurf {

namespace {

// Visits every fine cell with the eight coarse cells around its centre (at[c]: their
// indices, corner c = x + 2 y + 4 z) and their trilinear weights; combine returns the fine
// value. A fine cell's centre lies a quarter of a coarse cell from its parent's centre, so per
// axis the weights are 3/4 (parent) and 1/4 (the neighbour on the fine cell's side).
// Blocks: the fine block starts at twice the coarse block's offset (even), so i / 2 and i % 2
// hold for block indices too.
template <class Combine>
void prolongate_cells(Field& fine, Combine combine) {
  const int nfx = fine.nx(), nfy = fine.ny(), nfz = fine.nz();
#pragma omp parallel for schedule(static) if (nfx >= kParallelMinN)
  for (int k = 0; k < nfz; ++k)
    for (int j = 0; j < nfy; ++j)
      for (int i = 0; i < nfx; ++i) {
        const int ci = i / 2, cj = j / 2, ck = k / 2;
        const int di = i % 2 ? 1 : -1, dj = j % 2 ? 1 : -1, dk = k % 2 ? 1 : -1;
        int at[8][3];
        double weights[8];
        for (int c = 0; c < 8; ++c) {
          const int a = c & 1, b = (c >> 1) & 1, d = (c >> 2) & 1;
          weights[c] = (a ? 0.25 : 0.75) * (b ? 0.25 : 0.75) * (d ? 0.25 : 0.75);
          at[c][0] = ci + a * di;
          at[c][1] = cj + b * dj;
          at[c][2] = ck + d * dk;
        }
        fine(i, j, k) = combine(at, weights);
      }
}

}  // namespace

void prolongate_trilinear(const Field& coarse, Field& fine) {
  prolongate_cells(fine, [&](const int (&at)[8][3], const double (&w)[8]) {
    double v = 0.0;
    for (int c = 0; c < 8; ++c) v += w[c] * coarse(at[c][0], at[c][1], at[c][2]);
    return v;
  });
  fine.exchange_halo();
}

void prolongate_profile(const Field& coarse, Field& fine) {
  // psi on the coarse grid, once per cell (NaN outside the layer), instead of eight atanh per
  // fine cell: 0.93 s -> a tenth of that at 256^3, where most cells lie in the layer.
  Field psi = Field::like(coarse, 1);
  {
    const int nx = coarse.nx(), ny = coarse.ny(), nz = coarse.nz();
#pragma omp parallel for schedule(static) if (nx >= kParallelMinN)
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          const double y = 2.0 * coarse(i, j, k) - 1.0;
          psi(i, j, k) = std::abs(y) <= kProfileBand ? std::atanh(y)
                                                      : std::numeric_limits<double>::quiet_NaN();
        }
    psi.exchange_halo();
  }
  prolongate_cells(fine, [&](const int (&at)[8][3], const double (&w)[8]) {
    double v = 0.0, s = 0.0;
    for (int c = 0; c < 8; ++c) {
      v += w[c] * coarse(at[c][0], at[c][1], at[c][2]);
      s += w[c] * psi(at[c][0], at[c][1], at[c][2]);  // NaN if a corner lies outside the layer
    }
    return std::isnan(s) ? v : 0.5 * (1.0 + std::tanh(s));
  });
  // Restore the coarse mean by moving the interface, not the bulk: the correction is weighted
  // by phi (1 - phi), which vanishes in both phases.
  const int nx = fine.nx(), ny = fine.ny(), nz = fine.nz();
  auto layer = [](double phi) { return std::max(0.0, phi * (1.0 - phi)); };
  double weight = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : weight) if (nx >= kParallelMinN)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) weight += layer(fine(i, j, k));
  weight = fine.sum_over_ranks(weight) / fine.global_cells();
  const double missing = mass(coarse) - mass(fine);
  if (weight > 0.0) {
    const double c = missing / weight;
#pragma omp parallel for schedule(static) if (nx >= kParallelMinN)
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) fine(i, j, k) += c * layer(fine(i, j, k));
  } else {
    add_constant(fine, missing);
  }
  fine.exchange_halo();
}

bool series_settled(std::span<const double> values, double tol) {
  const std::size_t n = values.size();
  if (n < 4) return false;
  const double d3 = std::abs(values[n - 1] - values[n - 2]);
  const double d2 = std::abs(values[n - 2] - values[n - 3]);
  const double d1 = std::abs(values[n - 3] - values[n - 4]);
  if (d3 == 0.0) return true;
  if (!(d3 < d2 && d2 < d1)) return false;
  const double r = std::max(d3 / d2, d2 / d1);
  return d3 * r / (1.0 - r) <= tol;
}

}  // namespace cmcsurf
