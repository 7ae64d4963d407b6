// Periodic cell-centred scalar field on the unit cube with ghost layers.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "grid/halo.h"

namespace cmcsurf {

// Cache-line aligned allocator so that unit-stride loops start on a line.
template <class T>
struct AlignedAllocator {
  using value_type = T;
  static constexpr std::size_t kAlign = 64;
  AlignedAllocator() = default;
  template <class U>
  AlignedAllocator(const AlignedAllocator<U>&) {}
  T* allocate(std::size_t n) {
    return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(kAlign)));
  }
  void deallocate(T* p, std::size_t) { ::operator delete(p, std::align_val_t(kAlign)); }
  template <class U>
  bool operator==(const AlignedAllocator<U>&) const { return true; }
};

// An N^3 field, h = 1/N, cell i centred at x_i = (i + 1/2) h for i = 0..N-1
// (the paper's x_i = (i - 1/2) h with 1-based i). Ghost layers of width g
// surround the interior so that stencils never wrap indices.
class Field {
 public:
  Field() = default;
  Field(int n, int ghost);

  int n() const { return n_; }
  int ghost() const { return ghost_; }
  double h() const { return 1.0 / n_; }

  // Strides of the padded storage: x is unit stride.
  std::ptrdiff_t stride_y() const { return sy_; }
  std::ptrdiff_t stride_z() const { return sz_; }
  std::ptrdiff_t index(int i, int j, int k) const {
    return (k + ghost_) * sz_ + (j + ghost_) * sy_ + (i + ghost_);
  }
  double& operator()(int i, int j, int k) { return data_[index(i, j, k)]; }
  const double& operator()(int i, int j, int k) const { return data_[index(i, j, k)]; }

  double* data() { return data_.data(); }
  const double* data() const { return data_.data(); }
  std::size_t storage_size() const { return data_.size(); }
  std::size_t interior_size() const { return std::size_t(n_) * n_ * n_; }

  // Halo-exchange plan for this field's geometry (shared by fields of one level).
  const HaloPlan& halo_plan() const { return *plan_; }

  void fill(double value);  // interior and ghosts
  void exchange_halo() { apply_halo(*plan_, *this); }

 private:
  int n_ = 0;
  int ghost_ = 0;
  std::ptrdiff_t sy_ = 0;
  std::ptrdiff_t sz_ = 0;
  std::vector<double, AlignedAllocator<double>> data_;
  std::shared_ptr<const HaloPlan> plan_;
};

// Grids smaller than this run their loops on one thread: a parallel region costs a barrier,
// and coarse multigrid levels have too little work to pay for it (on a loaded machine a
// barrier can wait a whole scheduler quantum for a descheduled thread).
constexpr int kParallelMinN = 32;

// Interior loop helper: calls f(i, j, k) for every interior cell, k outermost.
template <class F>
void for_each_cell(int n, F&& f) {
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) f(i, j, k);
}

// Copies the interior of src into dst (same n, any ghost widths).
void copy_interior(const Field& src, Field& dst);

// Adds c to every interior value (ghosts are left for the next halo exchange).
void add_constant(Field& f, double c);

}  // namespace cmcsurf
