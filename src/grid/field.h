// Periodic cell-centred scalar field on the unit cube with ghost layers: the whole N^3 grid,
// or one process's block of it (parallel/decomposition.h).
//
// The ghost rule (docs/architecture.md): a `const Field&` argument arrives with valid ghosts
// (equal to the periodic wrap of the interior, or to the neighbours' interior on a block), and
// a function that modifies a field leaves its ghosts valid, unless its name or its comment says
// that it reads or writes the interior only. halo_is_current() checks this on whole grids;
// kernels that read ghosts call it under CMCSURF_DCHECK (grid/check.h) in checked builds.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

#include "grid/check.h"
#include "grid/halo.h"
#include "parallel/decomposition.h"

namespace cmcsurf {

// Zero-filled storage of at least 64-byte alignment: buffers of 1 MiB and more are anonymous
// memory mappings, which the kernel hands out zeroed page by page on first
// touch, so a new N^3 field costs no serial memset pass and its pages are faulted in by the
// parallel kernel that first writes them (a fifth of a 256^3 run's time went to zeroing new
// fields before); smaller ones are zeroed here. (Advising huge pages made the first touch 1 s
// slower at 256^3 here: with defrag=madvise the kernel compacts memory on the fault.)
void* allocate_zeroed(std::size_t bytes);
void release_zeroed(void* p, std::size_t bytes);

// Cache-line aligned allocator whose memory arrives zeroed (allocate_zeroed), so that
// value-initialising construction does nothing: a vector of n doubles built with it is zero
// without writing them. Only for vectors sized once (Field's storage): a vector that shrinks and
// grows again would show its old values.
template <class T>
struct AlignedAllocator {
  using value_type = T;
  static constexpr std::size_t kAlign = 64;
  AlignedAllocator() = default;
  template <class U>
  AlignedAllocator(const AlignedAllocator<U>&) {}
  T* allocate(std::size_t n) { return static_cast<T*>(allocate_zeroed(n * sizeof(T))); }
  void deallocate(T* p, std::size_t n) { release_zeroed(p, n * sizeof(T)); }
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;  // default-initialised: the memory is zero already
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
  template <class U>
  bool operator==(const AlignedAllocator<U>&) const { return true; }
};

// A field on the N^3 grid, h = 1/N, cell i centred at x_i = (i + 1/2) h for i = 0..N-1
// (the paper's x_i = (i - 1/2) h with 1-based i). This process stores the block of
// nx x ny x nz cells starting at global cell (ox, oy, oz) (the whole grid without a
// decomposition); local index (i, j, k) is global cell (ox + i, oy + j, oz + k). Ghost layers
// of width g surround the block so that stencils never wrap indices.
class Field {
 public:
  Field() = default;
  Field(int n, int ghost);  // the whole grid on this process
  // This process's block of the n^3 grid of decomposition d.
  Field(int n, int ghost, std::shared_ptr<const Decomposition> d);
  // Same grid and block as `like`, with another ghost width.
  static Field like(const Field& like, int ghost);

  int n() const { return n_; }  // global cells per side (mesh width 1/n)
  int nx() const { return size_[0]; }
  int ny() const { return size_[1]; }
  int nz() const { return size_[2]; }
  const std::array<int, 3>& size() const { return size_; }
  const std::array<int, 3>& offset() const { return offset_; }
  // Red-black colour of local cell (0, 0, 0): parity of its global index sum.
  int offset_parity() const { return (offset_[0] + offset_[1] + offset_[2]) & 1; }
  bool whole() const { return size_[0] == n_ && size_[1] == n_ && size_[2] == n_; }
  int ghost() const { return ghost_; }
  double h() const { return 1.0 / n_; }

  // Strides of the padded storage: x is unit stride.
  std::ptrdiff_t stride_y() const { return sy_; }
  std::ptrdiff_t stride_z() const { return sz_; }
  std::ptrdiff_t index(int i, int j, int k) const {
    return (k + ghost_) * sz_ + (j + ghost_) * sy_ + (i + ghost_);
  }
  double& operator()(int i, int j, int k) {
    CMCSURF_DCHECK(in_storage(i, j, k));
    return data_[index(i, j, k)];
  }
  const double& operator()(int i, int j, int k) const {
    CMCSURF_DCHECK(in_storage(i, j, k));
    return data_[index(i, j, k)];
  }
  // Whether local cell (i, j, k) lies in the interior or the ghost layers.
  bool in_storage(int i, int j, int k) const {
    return i >= -ghost_ && i < size_[0] + ghost_ && j >= -ghost_ && j < size_[1] + ghost_ &&
           k >= -ghost_ && k < size_[2] + ghost_;
  }

  double* data() { return data_.data(); }
  const double* data() const { return data_.data(); }
  std::size_t storage_size() const { return data_.size(); }
  // Cells of this process's block, and of the whole grid.
  std::size_t interior_size() const { return std::size_t(size_[0]) * size_[1] * size_[2]; }
  double global_cells() const { return double(n_) * n_ * n_; }

  // Halo-exchange plan for this field's geometry. Each field builds its own when it is
  // constructed (a copy of the field shares it); fields of one level do not share plans.
  const HaloPlan& halo_plan() const { return *plan_; }
  // The processes sharing the grid (null for a field that this process holds whole).
  const Decomposition* decomposition() const {
    return plan_ ? plan_->decomposition.get() : nullptr;
  }
  // The same, shared (for fields on another grid of the same processes).
  std::shared_ptr<const Decomposition> shared_decomposition() const {
    return plan_ ? plan_->decomposition : nullptr;
  }
  // Sums of per-process partial sums (identity on one process); every process gets the same.
  double sum_over_ranks(double local) const {
    return plan_->decomposition ? plan_->decomposition->sum(local) : local;
  }
  void sum_over_ranks(double* values, int count) const {
    if (plan_->decomposition) plan_->decomposition->sum(values, count);
  }

  void fill(double value);  // interior and ghosts (so the ghosts stay valid)
  // Makes the ghosts valid: periodic wrap, or the neighbours' faces on a block (collective).
  void exchange_halo() { apply_halo(*plan_, *this); }

 private:
  void allocate(const Block& b, int ghost, std::shared_ptr<const Decomposition> d);
  int n_ = 0;
  std::array<int, 3> size_{};
  std::array<int, 3> offset_{};
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

// Interior loop helper: calls f(i, j, k) for every interior cell of an n^3 grid, k outermost.
template <class F>
void for_each_cell(int n, F&& f) {
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) f(i, j, k);
}
// The same over a field's (local) block.
template <class F>
void for_each_cell(const Field& field, F&& f) {
  for (int k = 0; k < field.nz(); ++k)
    for (int j = 0; j < field.ny(); ++j)
      for (int i = 0; i < field.nx(); ++i) f(i, j, k);
}

// Halo exchange of two fields of the same geometry (phi and nu) in one pass of messages.
inline void exchange_halos(Field& a, Field& b) {
  Field* const fields[2] = {&a, &b};
  apply_halo(a.halo_plan(), fields, 2);
}

// Whether the ghosts of a whole-grid field equal the periodic wrap of its interior, bit for
// bit (NaN included). On a block of a decomposed grid the neighbours' values live on other
// processes: it checks nothing there and returns true. Cost: one pass over the ghost cells.
bool halo_is_current(const Field& f);

// Copies the interior of src into dst (same block, any ghost widths); dst's ghosts are not
// written (interior only: exchange dst's halo before reading them).
void copy_interior(const Field& src, Field& dst);

// Adds c to every value, ghosts included: valid ghosts stay valid.
void add_constant(Field& f, double c);

// A stencil that reads `needed` ghost layers refuses a narrower field: throws
// std::invalid_argument naming `who`, the width needed and the width given.
void require_ghost(const Field& f, int needed, const char* who);

// Mean of the interior values over the whole grid (the per-process sums are added over the
// processes; every process gets the same value). For phi this is the conserved mass.
double mean(const Field& f);

// The whole grid from the blocks of a decomposed field, on every process (all) or on rank 0
// only (`whole` is left untouched elsewhere). A whole field is copied. whole: Field(n, g); its
// halo is exchanged (ghosts valid on return). block is read in the interior only.
void gather_field(const Field& block, Field& whole, bool all);
// This process's block of a whole field held by every process. Interior only: block's ghosts
// are not written.
void take_block(const Field& whole, Field& block);

}  // namespace cmcsurf
