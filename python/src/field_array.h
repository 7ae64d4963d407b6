// NumPy (N, N, N) arrays indexed [i, j, k] <-> whole-grid Fields with ghost 2: the copies that
// module.cpp's run functions and analysis.cpp's bindings share. They check what every caller
// needs (finite values); the accepted shapes differ by caller and are checked there.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cmath>
#include <cstddef>

#include <fmt/format.h>

#include "grid/field.h"

namespace cmcsurf::python {

// The C-contiguous float64 values v of an (n, n, n) array as a Field with valid ghosts; a
// non-finite value is a ValueError naming `name` and the index.
inline Field field_from_cube(const double* v, int n, const char* name) {
  Field f(n, 2);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const double x = v[(std::size_t(i) * n + j) * n + k];
        if (!std::isfinite(x))
          throw pybind11::value_error(fmt::format(
              "{}: {} at [{}, {}, {}]; accepted: finite values", name, x, i, j, k));
        f(i, j, k) = x;
      }
  f.exchange_halo();
  return f;
}

// A copy of the interior as a new, writable C-contiguous (N, N, N) float64 array.
inline pybind11::array_t<double> cube_from_field(const Field& f) {
  const int n = f.n();
  pybind11::array_t<double> out({n, n, n});
  double* a = out.mutable_data();
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) a[(std::size_t(i) * n + j) * n + k] = f(i, j, k);
  return out;
}

}  // namespace cmcsurf::python
