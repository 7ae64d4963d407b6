#include "grid/field.h"

#include <algorithm>
#include <cassert>
#include <cstring>

namespace cmcsurf {

Field::Field(int n, int ghost) : n_(n), ghost_(ghost) {
  assert(n > 0 && ghost >= 0 && ghost <= n);
  const std::ptrdiff_t p = n + 2 * ghost;
  sy_ = p;
  sz_ = p * p;
  data_.assign(std::size_t(p * p * p), 0.0);
  plan_ = make_periodic_halo_plan(n, ghost);
}

void Field::fill(double value) { std::fill(data_.begin(), data_.end(), value); }

void copy_interior(const Field& src, Field& dst) {
  assert(src.n() == dst.n());
  const int n = src.n();
#pragma omp parallel for schedule(static) if (n >= kParallelMinN)
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      std::memcpy(&dst(0, j, k), &src(0, j, k), sizeof(double) * n);
}

void add_constant(Field& f, double c) {
  const int n = f.n();
#pragma omp parallel for schedule(static) if (n >= kParallelMinN)
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j) {
      double* p = &f(0, j, k);
      for (int i = 0; i < n; ++i) p[i] += c;
    }
}

}  // namespace cmcsurf
