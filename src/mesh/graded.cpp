#include "mesh/graded.h"

#include <fmt/format.h>

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <utility>

namespace cmcsurf {

double graded_target(const GradedRamp& ramp, const std::array<int, 3>& tiles, double s) {
  return ramp.from_fraction + (ramp.to_fraction - ramp.from_fraction) * s / tiles[ramp.axis];
}

TiledSampler graded_sampler(std::vector<GradedMember> members, const GradedRamp& ramp,
                            const std::array<int, 3>& tiles, double fraction_tol) {
  if (members.size() < 2) throw std::invalid_argument("graded: needs at least two members");
  const int n = members[0].phi.n();
  for (const GradedMember& m : members)
    if (!m.phi.whole())
      throw std::invalid_argument("graded: members must be whole grids, not blocks of a split one");
  for (std::size_t m = 1; m < members.size(); ++m) {
    if (members[m].phi.n() != n)
      throw std::invalid_argument(fmt::format(
          "graded: members have grids {} and {}; all must match", n, members[m].phi.n()));
    if (!(members[m].volume_fraction > members[m - 1].volume_fraction))
      throw std::invalid_argument("graded: member volume fractions must increase strictly");
  }
  const double lo = members.front().volume_fraction, hi = members.back().volume_fraction;
  for (double a : {ramp.from_fraction, ramp.to_fraction})
    if (!(a >= lo - fraction_tol && a <= hi + fraction_tol))
      throw std::invalid_argument(fmt::format(
          "graded: volume fraction {} is outside the members' range [{:.6f}, {:.6f}] (+- {:g})",
          a, lo, hi, fraction_tol));
  // Shared, so that copies of the sampler (a std::function) do not copy the fields.
  auto owned = std::make_shared<const std::vector<GradedMember>>(std::move(members));
  return [owned, ramp, tiles, n](int i, int j, int k) {
    const std::vector<GradedMember>& members = *owned;
    const int idx[3] = {i, j, k};
    const double s = (idx[ramp.axis] + 0.5) / n;
    const double a = graded_target(ramp, tiles, s);
    std::size_t m = 1;
    while (m + 1 < members.size() && members[m].volume_fraction < a) ++m;
    const GradedMember &p = members[m - 1], &q = members[m];
    const double w =
        std::clamp((a - p.volume_fraction) / (q.volume_fraction - p.volume_fraction), 0.0, 1.0);
    const int ii = i % n, jj = j % n, kk = k % n;
    return (1.0 - w) * p.phi(ii, jj, kk) + w * q.phi(ii, jj, kk);
  };
}

nlohmann::json graded_cell_report(const TiledSampler& f, int n, const GradedRamp& ramp,
                                  const std::array<int, 3>& tiles) {
  nlohmann::json cells = nlohmann::json::array();
  for (int tz = 0; tz < tiles[2]; ++tz)
    for (int ty = 0; ty < tiles[1]; ++ty)
      for (int tx = 0; tx < tiles[0]; ++tx) {
        long inside = 0;
        for (int k = 0; k < n; ++k)
          for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
              inside += f(tx * n + i, ty * n + j, tz * n + k) > 0.5;
        const int t[3] = {tx, ty, tz};
        cells.push_back({{"tile", {tx, ty, tz}},
                         {"target", graded_target(ramp, tiles, t[ramp.axis] + 0.5)},
                         {"achieved", double(inside) / (double(n) * n * n)}});
      }
  return cells;
}

}  // namespace cmcsurf
