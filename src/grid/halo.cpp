#include "grid/halo.h"

#include <cstring>

#include "grid/field.h"
#include "parallel/decomposition.h"

namespace cmcsurf {

std::shared_ptr<const HaloPlan> make_halo_plan(const std::array<int, 3>& size, int ghost,
                                               std::shared_ptr<const Decomposition> d) {
  auto plan = std::make_shared<HaloPlan>();
  plan->size = size;
  plan->ghost = ghost;
  if (d && d->distributed()) plan->decomposition = std::move(d);
  if (ghost == 0) return plan;
  for (int axis = 0; axis < 3; ++axis) {
    const int n = size[axis];
    plan->slabs.push_back({axis, n - ghost, -ghost, ghost});  // low ghosts <- top interior
    plan->slabs.push_back({axis, 0, n, ghost});               // high ghosts <- bottom interior
  }
  return plan;
}

std::shared_ptr<const HaloPlan> make_periodic_halo_plan(int n, int ghost) {
  return make_halo_plan({n, n, n}, ghost, nullptr);
}

namespace {

// Range along `other` axis for a slab normal to `axis`: axes handled before
// `axis` (lower index) include their ghosts.
void slab_range(int axis, int other, const std::array<int, 3>& size, int g, int* lo, int* hi) {
  if (other < axis) {
    *lo = -g;
    *hi = size[other] + g;
  } else {
    *lo = 0;
    *hi = size[other];
  }
}

// Runs this short are copied by a loop (see local_copy).
constexpr int kShortRun = 4;

// Calls row(start_pointer_offset, length) for each contiguous run of the planes
// start..start+width-1 normal to s.axis, in a fixed order (the packing order).
template <class Row>
void for_each_run(const Field& f, const HaloSlab& s, int start, const int lo[3], const int hi[3],
                  Row&& row) {
  if (s.axis == 0) {
    for (int k = lo[2]; k < hi[2]; ++k)
      for (int j = lo[1]; j < hi[1]; ++j) row(f.index(start, j, k), s.width);
  } else if (s.axis == 1) {
    const int len = hi[0] - lo[0];
    for (int k = lo[2]; k < hi[2]; ++k)
      for (int w = 0; w < s.width; ++w) row(f.index(lo[0], start + w, k), len);
  } else {
    const int len = hi[0] - lo[0];
    for (int w = 0; w < s.width; ++w)
      for (int j = lo[1]; j < hi[1]; ++j) row(f.index(lo[0], j, start + w), len);
  }
}

void local_copy(const HaloSlab& s, const int lo[3], const int hi[3], Field& f) {
  double* d = f.data();
  // Offset between source and destination planes.
  std::ptrdiff_t delta = 0;
  if (s.axis == 0) delta = f.index(s.dst_start, 0, 0) - f.index(s.src_start, 0, 0);
  if (s.axis == 1) delta = f.index(0, s.dst_start, 0) - f.index(0, s.src_start, 0);
  if (s.axis == 2) delta = f.index(0, 0, s.dst_start) - f.index(0, 0, s.src_start);
  for_each_run(f, s, s.src_start, lo, hi, [&](std::ptrdiff_t at, int len) {
    // The x faces are runs of one or two ghosts per row: a library call for each cost more
    // than the copy (memmove was 8 % of a 128^3 run's samples, mostly these).
    if (len <= kShortRun) {
      // A fixed trip count, so that the compiler unrolls it instead of calling memmove.
      for (int i = 0; i < kShortRun; ++i)
        if (i < len) d[at + delta + i] = d[at + i];
    } else {
      std::memcpy(d + at + delta, d + at, sizeof(double) * len);
    }
  });
}

}  // namespace

void apply_halo(const HaloPlan& plan, Field& field) {
  Field* const fields[1] = {&field};
  apply_halo(plan, fields, 1);
}

void apply_halo(const HaloPlan& plan, Field* const* fields, int nf) {
  const int g = plan.ghost;
  for (int f = 0; f < nf; ++f)
    CMCSURF_CHECK(fields[f]->size() == plan.size && fields[f]->ghost() == g);
  for (std::size_t s = 0; s < plan.slabs.size(); s += 2) {
    const HaloSlab& up = plan.slabs[s];        // low ghosts <- top interior
    const HaloSlab& down = plan.slabs[s + 1];  // high ghosts <- bottom interior
    const int axis = up.axis;
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) slab_range(axis, a, plan.size, g, &lo[a], &hi[a]);
    if (!plan.decomposition || plan.decomposition->dims()[axis] == 1) {
      for (int f = 0; f < nf; ++f) {
        local_copy(up, lo, hi, *fields[f]);
        local_copy(down, lo, hi, *fields[f]);
      }
      continue;
    }
    // Pack both faces of every field, exchange with the neighbours, unpack into the ghosts.
    std::size_t face = up.width;
    for (int a = 0; a < 3; ++a)
      if (a != axis) face *= std::size_t(hi[a] - lo[a]);
    const std::size_t count = face * nf;
    std::vector<double>& buf = plan.buffer;
    buf.resize(4 * count);
    double* send_lo = buf.data();
    double* send_hi = send_lo + count;
    double* recv_lo = send_hi + count;
    double* recv_hi = recv_lo + count;
    for (int f = 0; f < nf; ++f) {
      const Field& field = *fields[f];
      const double* d = field.data();
      double* out_hi = send_hi + f * face;
      double* out_lo = send_lo + f * face;
      for_each_run(field, up, up.src_start, lo, hi, [&](std::ptrdiff_t at, int len) {
        std::memcpy(out_hi, d + at, sizeof(double) * len);
        out_hi += len;
      });
      for_each_run(field, down, down.src_start, lo, hi, [&](std::ptrdiff_t at, int len) {
        std::memcpy(out_lo, d + at, sizeof(double) * len);
        out_lo += len;
      });
    }
    plan.decomposition->exchange(axis, send_lo, send_hi, recv_lo, recv_hi, count);
    for (int f = 0; f < nf; ++f) {
      double* d = fields[f]->data();
      const double* in_lo = recv_lo + f * face;
      const double* in_hi = recv_hi + f * face;
      for_each_run(*fields[f], up, up.dst_start, lo, hi, [&](std::ptrdiff_t at, int len) {
        std::memcpy(d + at, in_lo, sizeof(double) * len);
        in_lo += len;
      });
      for_each_run(*fields[f], down, down.dst_start, lo, hi, [&](std::ptrdiff_t at, int len) {
        std::memcpy(d + at, in_hi, sizeof(double) * len);
        in_hi += len;
      });
    }
  }
}

}  // namespace cmcsurf
