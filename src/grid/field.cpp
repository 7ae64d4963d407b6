#include "grid/field.h"

#include <algorithm>
#include <cassert>
#include <cstring>

namespace cmcsurf {

Field::Field(int n, int ghost) {
  Block b;
  b.n = n;
  b.size = {n, n, n};
  allocate(b, ghost, nullptr);
}

Field::Field(int n, int ghost, std::shared_ptr<const Decomposition> d) {
  if (!d || !d->distributed()) {
    *this = Field(n, ghost);
    return;
  }
  for (int a = 0; a < 3; ++a) assert(n % d->dims()[a] == 0);
  const Block b = d->block(n);
  allocate(b, ghost, std::move(d));
}

Field Field::like(const Field& like, int ghost) {
  if (!like.decomposition()) return Field(like.n(), ghost);
  return Field(like.n(), ghost, like.plan_->decomposition);
}

void Field::allocate(const Block& b, int ghost, std::shared_ptr<const Decomposition> d) {
  n_ = b.n;
  size_ = b.size;
  offset_ = b.offset;
  ghost_ = ghost;
  assert(n_ > 0 && ghost >= 0);
  assert(ghost <= size_[0] && ghost <= size_[1] && ghost <= size_[2]);
  const std::ptrdiff_t px = size_[0] + 2 * ghost, py = size_[1] + 2 * ghost,
                       pz = size_[2] + 2 * ghost;
  sy_ = px;
  sz_ = px * py;
  data_.assign(std::size_t(px * py * pz), 0.0);
  plan_ = d ? make_halo_plan(size_, ghost, std::move(d)) : make_periodic_halo_plan(n_, ghost);
}

void Field::fill(double value) { std::fill(data_.begin(), data_.end(), value); }

void copy_interior(const Field& src, Field& dst) {
  assert(src.size() == dst.size());
  const int nx = src.nx(), ny = src.ny(), nz = src.nz();
#pragma omp parallel for schedule(static) if (nx >= kParallelMinN)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      std::memcpy(&dst(0, j, k), &src(0, j, k), sizeof(double) * nx);
}

void add_constant(Field& f, double c) {
  const int nx = f.nx(), ny = f.ny(), nz = f.nz();
#pragma omp parallel for schedule(static) if (nx >= kParallelMinN)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      double* p = &f(0, j, k);
      for (int i = 0; i < nx; ++i) p[i] += c;
    }
}

void gather_field(const Field& block, Field& whole, bool all) {
  const Decomposition* d = block.decomposition();
  if (!d) {
    copy_interior(block, whole);
    whole.exchange_halo();
    return;
  }
  const std::size_t count = block.interior_size();
  std::vector<double> mine(count);
  double* out = mine.data();
  for (int k = 0; k < block.nz(); ++k)
    for (int j = 0; j < block.ny(); ++j, out += block.nx())
      std::memcpy(out, &block(0, j, k), sizeof(double) * block.nx());
  const bool receives = all || d->rank() == 0;
  std::vector<double> every(receives ? count * d->ranks() : 0);
  if (all)
    d->allgather(mine.data(), count, every.data());
  else
    d->gather(mine.data(), count, every.data());
  if (!receives) return;
  assert(whole.whole() && whole.n() == block.n());
  for (int r = 0; r < d->ranks(); ++r) {
    const Block b = d->block_of(r, block.n());
    const double* in = every.data() + std::size_t(r) * count;
    for (int k = 0; k < b.size[2]; ++k)
      for (int j = 0; j < b.size[1]; ++j, in += b.size[0])
        std::memcpy(&whole(b.offset[0], b.offset[1] + j, b.offset[2] + k), in,
                    sizeof(double) * b.size[0]);
  }
  whole.exchange_halo();
}

void take_block(const Field& whole, Field& block) {
  assert(whole.whole() && whole.n() == block.n());
  const auto& o = block.offset();
  for (int k = 0; k < block.nz(); ++k)
    for (int j = 0; j < block.ny(); ++j)
      std::memcpy(&block(0, j, k), &whole(o[0], o[1] + j, o[2] + k), sizeof(double) * block.nx());
}

}  // namespace cmcsurf
