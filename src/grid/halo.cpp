#include "grid/halo.h"

#include <cstring>

#include "grid/field.h"

namespace cmcsurf {

std::shared_ptr<const HaloPlan> make_periodic_halo_plan(int n, int ghost) {
  auto plan = std::make_shared<HaloPlan>();
  plan->n = n;
  plan->ghost = ghost;
  if (ghost == 0) return plan;
  for (int axis = 0; axis < 3; ++axis) {
    plan->slabs.push_back({axis, n - ghost, -ghost, ghost});  // low ghosts <- top interior
    plan->slabs.push_back({axis, 0, n, ghost});               // high ghosts <- bottom interior
  }
  return plan;
}

namespace {

// Range along `other` axis for a slab normal to `axis`: axes handled before
// `axis` (lower index) include their ghosts.
void slab_range(int axis, int other, int n, int g, int* lo, int* hi) {
  if (other < axis) {
    *lo = -g;
    *hi = n + g;
  } else {
    *lo = 0;
    *hi = n;
  }
}

}  // namespace

void apply_halo(const HaloPlan& plan, Field& f) {
  const int n = plan.n, g = plan.ghost;
  for (const HaloSlab& s : plan.slabs) {
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) slab_range(s.axis, a, n, g, &lo[a], &hi[a]);
    if (s.axis == 0) {
      // Planes normal to x: strided copies of `width` contiguous values per row.
      for (int k = lo[2]; k < hi[2]; ++k)
        for (int j = lo[1]; j < hi[1]; ++j)
          std::memcpy(&f(s.dst_start, j, k), &f(s.src_start, j, k), sizeof(double) * s.width);
    } else if (s.axis == 1) {
      const int len = hi[0] - lo[0];
      for (int k = lo[2]; k < hi[2]; ++k)
        for (int w = 0; w < s.width; ++w)
          std::memcpy(&f(lo[0], s.dst_start + w, k), &f(lo[0], s.src_start + w, k),
                      sizeof(double) * len);
    } else {
      const int len = hi[0] - lo[0];
      for (int w = 0; w < s.width; ++w)
        for (int j = lo[1]; j < hi[1]; ++j)
          std::memcpy(&f(lo[0], j, s.dst_start + w), &f(lo[0], j, s.src_start + w),
                      sizeof(double) * len);
    }
  }
}

}  // namespace cmcsurf
