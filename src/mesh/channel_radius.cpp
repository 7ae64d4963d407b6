#include "mesh/channel_radius.h"

namespace cmcsurf {

ThicknessStats channel_radius_of(const std::vector<std::uint8_t>& inside, int n) {
  // local_thickness reports 2 r - 1 for a ball of radius r voxels (the voxel centres it spans):
  // r is the distance from the ball's centre voxel to the nearest voxel centre outside.
  std::vector<double> r = local_thickness(inside, n);
  for (std::size_t c = 0; c < r.size(); ++c)
    if (inside[c]) r[c] = 0.5 * (r[c] + 1.0);
  return thickness_stats(r, inside, 1.0 / n);
}

ChannelRadius channel_radius(const Field& psi) {
  CMCSURF_CHECK(psi.whole());
  const int n = psi.n();
  std::vector<std::uint8_t> phase1(std::size_t(n) * n * n), phase2(phase1.size());
  for_each_cell(n, [&](int i, int j, int k) {
    const std::size_t c = (std::size_t(k) * n + j) * n + i;
    phase1[c] = psi(i, j, k) > 0.0;
    phase2[c] = !phase1[c];
  });
  ChannelRadius r;
  r.phase1 = channel_radius_of(phase1, n);
  r.phase2 = channel_radius_of(phase2, n);
  return r;
}

}  // namespace cmcsurf
