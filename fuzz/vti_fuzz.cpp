// The VTI reader (io/vti.h) on arbitrary bytes: it either returns N^3 finite values per array
// or throws std::runtime_error naming the problem.
#include <cmath>
#include <stdexcept>

#include "fuzz_target.h"
#include "io/vti.h"

namespace {

using cmcsurf::fuzz::require;

void check_parsed(const cmcsurf::VtiData& data, const cmcsurf::VtiReadOptions& options) {
  require(data.n >= 1 && data.n <= options.max_n, "N out of range");
  require(!data.arrays.empty(), "no arrays");
  for (const auto& [name, f] : data.arrays) {
    require(!name.empty() && f.n() == data.n, "array '" + name + "' has the wrong N");
    for (int k = 0; k < data.n; ++k)
      for (int j = 0; j < data.n; ++j)
        for (int i = 0; i < data.n; ++i)
          require(std::isfinite(f(i, j, k)), "array '" + name + "' holds a non-finite value");
    require(cmcsurf::halo_is_current(f), "array '" + name + "' has stale ghosts");
  }
}

}  // namespace

CMCSURF_FUZZ_TARGET(vti) {
  cmcsurf::VtiReadOptions options;
  options.max_n = 64;  // a fuzz input is small; bigger N is refused before allocating
  cmcsurf::VtiData all;
  try {
    all = cmcsurf::parse_vti(input, options, "fuzz input");
  } catch (const std::runtime_error&) {
    return cmcsurf::fuzz::Outcome::refused;
  }
  check_parsed(all, options);
  // Reading one array alone (as mesh --from reads phi) gives the same values.
  options.only = all.arrays.begin()->first;
  const cmcsurf::VtiData one = cmcsurf::parse_vti(input, options, "fuzz input");
  require(one.arrays.size() == 1 && one.n == all.n, "only= read a different shape");
  const cmcsurf::Field& a = one.arrays.begin()->second;
  const cmcsurf::Field& b = all.arrays.begin()->second;
  for (int k = 0; k < all.n; ++k)
    for (int j = 0; j < all.n; ++j)
      for (int i = 0; i < all.n; ++i)
        require(a(i, j, k) == b(i, j, k), "only= read different values");
  return cmcsurf::fuzz::Outcome::parsed;
}
