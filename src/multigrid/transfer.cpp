#include "multigrid/transfer.h"

namespace cmcsurf {

namespace {

// The coarse block covers the fine block's cells in pairs along every axis.
bool is_coarsening(const Field& fine, const Field& coarse) {
  for (int a = 0; a < 3; ++a)
    if (fine.size()[a] != 2 * coarse.size()[a] || fine.offset()[a] != 2 * coarse.offset()[a])
      return false;
  return fine.n() == 2 * coarse.n();
}

}  // namespace

void restrict_average(const Field& fine, Field& coarse) {
  CMCSURF_CHECK(is_coarsening(fine, coarse));
  const int ncx = coarse.nx(), ncy = coarse.ny(), ncz = coarse.nz();
  const std::ptrdiff_t fy = fine.stride_y(), fz = fine.stride_z();
#pragma omp parallel for schedule(static) if (fine.nx() >= kParallelMinN)
  for (int k = 0; k < ncz; ++k)
    for (int j = 0; j < ncy; ++j) {
      const double* f = &fine(0, 2 * j, 2 * k);
      double* c = &coarse(0, j, k);
      for (int i = 0; i < ncx; ++i) {
        const double* p = f + 2 * i;
        c[i] = 0.125 * ((p[0] + p[1]) + (p[fy] + p[fy + 1]) + (p[fz] + p[fz + 1]) +
                        (p[fy + fz] + p[fy + fz + 1]));
      }
    }
}

void restrict_average_ref(const Field& fine, Field& coarse) {
  CMCSURF_CHECK(is_coarsening(fine, coarse));
  for_each_cell(coarse, [&](int i, int j, int k) {
    double sum = 0.0;
    for (int dk = 0; dk < 2; ++dk)
      for (int dj = 0; dj < 2; ++dj)
        for (int di = 0; di < 2; ++di) sum += fine(2 * i + di, 2 * j + dj, 2 * k + dk);
    coarse(i, j, k) = sum / 8.0;
  });
}

void add_interpolated_correction(const Field& coarse, const Field& coarse_before, Field& fine) {
  CMCSURF_CHECK(is_coarsening(fine, coarse) && coarse_before.size() == coarse.size());
  const int nfx = fine.nx(), nfy = fine.ny(), nfz = fine.nz();
#pragma omp parallel for schedule(static) if (nfx >= kParallelMinN)
  for (int k = 0; k < nfz; ++k)
    for (int j = 0; j < nfy; ++j) {
      const double* c = &coarse(0, j / 2, k / 2);
      const double* b = &coarse_before(0, j / 2, k / 2);
      double* f = &fine(0, j, k);
      for (int i = 0; i < nfx; ++i) f[i] += c[i / 2] - b[i / 2];
    }
}

void add_interpolated_correction_ref(const Field& coarse, const Field& coarse_before,
                                     Field& fine) {
  CMCSURF_CHECK(is_coarsening(fine, coarse) && coarse_before.size() == coarse.size());
  for_each_cell(fine, [&](int i, int j, int k) {
    fine(i, j, k) += coarse(i / 2, j / 2, k / 2) - coarse_before(i / 2, j / 2, k / 2);
  });
}

}  // namespace cmcsurf
