// An exception must not leave a thread of an OpenMP parallel region (std::terminate ends the
// process, e.g. a std::bad_alloc under a memory limit). A region's work runs through
// FirstException::run, which keeps the first exception any thread threw; after the region,
// rethrow() raises it on the calling thread, where the caller can handle it.
#pragma once

#include <atomic>
#include <exception>

namespace cmcsurf {

class FirstException {
 public:
  // Runs f(); an exception it throws is kept if it is the first, never propagated. True when
  // f() returned.
  template <class F>
  bool run(F&& f) noexcept {
    try {
      f();
      return true;
    } catch (...) {
      keep(std::current_exception());
      return false;
    }
  }
  // True once some thread's f() threw: later work may be skipped.
  bool failed() const noexcept { return failed_.load(std::memory_order_relaxed); }
  // After the region: rethrows the kept exception, if any.
  void rethrow() const;

 private:
  void keep(std::exception_ptr e) noexcept;

  std::exception_ptr error_;
  std::atomic<bool> failed_{false};
};

}  // namespace cmcsurf
