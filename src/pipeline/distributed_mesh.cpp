#include "pipeline/distributed_mesh.h"

#include <stdexcept>
#include <vector>

namespace cmcsurf {

namespace {

// Rank 0's requests, broadcast before each plane: a plane index, or one of these.
constexpr double kDone = -1.0;
constexpr double kFailed = -2.0;

// This process's part of z-plane k (nx x ny values, x fastest), or nothing when k is outside
// its block.
std::vector<double> plane_part(const Field& block, int k) {
  const int kl = k - block.offset()[2];
  if (kl < 0 || kl >= block.nz()) return {};
  std::vector<double> part(std::size_t(block.nx()) * block.ny());
  for (int j = 0; j < block.ny(); ++j)
    for (int i = 0; i < block.nx(); ++i) part[std::size_t(j) * block.nx() + i] = block(i, j, kl);
  return part;
}

}  // namespace

Scaffold distributed_surface_scaffold(const Field& block, const ScaffoldParams& p) {
  const Decomposition* d = block.decomposition();
  if (!d || !d->distributed()) return build_scaffold(block, p);
  const int n = block.n();
  if (d->rank() != 0) {  // serve planes until rank 0 is done
    while (true) {
      double request = 0.0;
      d->broadcast(&request, 1);
      if (request == kDone) return {};
      if (request == kFailed)
        throw std::runtime_error("the surface mesh failed on rank 0 (its message is above)");
      d->gather_varying(plane_part(block, int(request)));
    }
  }
  std::vector<double> plane(std::size_t(n) * n);
  const PlaneFn fetch = [&](int k) {
    double request = k;
    d->broadcast(&request, 1);
    std::vector<int> counts;
    const std::vector<double> parts = d->gather_varying(plane_part(block, k), &counts);
    std::size_t at = 0;
    for (int r = 0; r < d->ranks(); ++r) {
      if (counts[r] == 0) continue;
      const Block b = d->block_of(r, n);
      for (int j = 0; j < b.size[1]; ++j)
        for (int i = 0; i < b.size[0]; ++i)
          plane[std::size_t(b.offset[1] + j) * n + b.offset[0] + i] = parts[at++];
    }
    return static_cast<const double*>(plane.data());
  };
  Scaffold out;
  try {
    out = build_surface_scaffold(fetch, n, p);
  } catch (...) {
    double failed = kFailed;
    d->broadcast(&failed, 1);
    throw;
  }
  double done = kDone;
  d->broadcast(&done, 1);
  return out;
}

}  // namespace cmcsurf
