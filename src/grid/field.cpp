#include "grid/field.h"

#include <stdexcept>
#include <string>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>

#include <sys/mman.h>

namespace cmcsurf {

namespace {
constexpr std::size_t kMappedBytes = std::size_t(1) << 20;
}  // namespace

void* allocate_zeroed(std::size_t bytes) {
  if (bytes >= kMappedBytes) {
    void* p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    return p;
  }
  void* p = ::operator new(bytes, std::align_val_t(64));
  std::memset(p, 0, bytes);
  return p;
}

void release_zeroed(void* p, std::size_t bytes) {
  if (p == nullptr) return;
  if (bytes >= kMappedBytes)
    munmap(p, bytes);
  else
    ::operator delete(p, std::align_val_t(64));
}

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
  for (int a = 0; a < 3; ++a) CMCSURF_CHECK(n % d->dims()[a] == 0);
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
  CMCSURF_CHECK(n_ > 0 && ghost >= 0);
  CMCSURF_CHECK(ghost <= size_[0] && ghost <= size_[1] && ghost <= size_[2]);
  const std::ptrdiff_t px = size_[0] + 2 * ghost, py = size_[1] + 2 * ghost,
                       pz = size_[2] + 2 * ghost;
  sy_ = px;
  sz_ = px * py;
  data_.resize(std::size_t(px * py * pz));  // zero: AlignedAllocator's memory
  plan_ = d ? make_halo_plan(size_, ghost, std::move(d)) : make_periodic_halo_plan(n_, ghost);
}

void check_failed(const char* condition, const char* file, int line) {
  std::fprintf(stderr, "cmcsurf: check failed: %s at %s:%d\n", condition, file, line);
  std::fflush(stderr);
  std::abort();
}

void Field::fill(double value) { std::fill(data_.begin(), data_.end(), value); }

bool halo_is_current(const Field& f) {
  const int n = f.n(), g = f.ghost();
  if (g == 0 || !f.whole()) return true;
  auto wrap = [n](int i) { return ((i % n) + n) % n; };
  const std::size_t bytes_g = sizeof(double) * g, bytes_n = sizeof(double) * n;
  for (int k = -g; k < n + g; ++k)
    for (int j = -g; j < n + g; ++j) {
      const double* row = &f(0, j, k);
      if (j >= 0 && j < n && k >= 0 && k < n) {  // an interior row: its two ghost ends
        if (std::memcmp(row - g, row + n - g, bytes_g) != 0 ||
            std::memcmp(row + n, row, bytes_g) != 0)
          return false;
      } else {  // a ghost row: the whole padded row against its periodic image
        const double* image = &f(0, wrap(j), wrap(k));
        if (std::memcmp(row - g, image + n - g, bytes_g) != 0 ||
            std::memcmp(row, image, bytes_n) != 0 || std::memcmp(row + n, image, bytes_g) != 0)
          return false;
      }
    }
  return true;
}

double mean(const Field& f) {
  const int nx = f.nx(), ny = f.ny(), nz = f.nz();
  double sum = 0.0;
#pragma omp parallel for reduction(+ : sum) schedule(static) if (nx >= kParallelMinN)
  for (int k = 0; k < nz; ++k) {
    double plane = 0.0;
    for (int j = 0; j < ny; ++j) {
      const double* row = &f(0, j, k);
      double s = 0.0;
#pragma omp simd reduction(+ : s)
      for (int i = 0; i < nx; ++i) s += row[i];
      plane += s;
    }
    sum += plane;
  }
  return f.sum_over_ranks(sum) / f.global_cells();
}

void copy_interior(const Field& src, Field& dst) {
  CMCSURF_CHECK(src.size() == dst.size());
  const int nx = src.nx(), ny = src.ny(), nz = src.nz();
#pragma omp parallel for schedule(static) if (nx >= kParallelMinN)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      std::memcpy(&dst(0, j, k), &src(0, j, k), sizeof(double) * nx);
}

void add_constant(Field& f, double c) {
  double* p = f.data();
  const std::ptrdiff_t size = std::ptrdiff_t(f.storage_size());
#pragma omp parallel for schedule(static) if (f.nx() >= kParallelMinN)
  for (std::ptrdiff_t i = 0; i < size; ++i) p[i] += c;
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
  CMCSURF_CHECK(whole.whole() && whole.n() == block.n());
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
  CMCSURF_CHECK(whole.whole() && whole.n() == block.n());
  const auto& o = block.offset();
  for (int k = 0; k < block.nz(); ++k)
    for (int j = 0; j < block.ny(); ++j)
      std::memcpy(&block(0, j, k), &whole(o[0], o[1] + j, o[2] + k), sizeof(double) * block.nx());
}

void require_ghost(const Field& f, int needed, const char* who) {
  if (f.ghost() < needed)
    throw std::invalid_argument(std::string(who) + ": needs ghost >= " + std::to_string(needed) +
                                ", got " + std::to_string(f.ghost()));
}

}  // namespace cmcsurf
