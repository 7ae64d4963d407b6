#include "parallel/first_exception.h"

namespace cmcsurf {

void FirstException::keep(std::exception_ptr e) noexcept {
#pragma omp critical(cmcsurf_first_exception)
  if (!error_) error_ = std::move(e);
  failed_.store(true, std::memory_order_relaxed);
}

void FirstException::rethrow() const {
  if (error_) std::rethrow_exception(error_);
}

}  // namespace cmcsurf
