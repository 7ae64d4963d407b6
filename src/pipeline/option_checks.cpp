#include "pipeline/option_checks.h"

#include <fmt/format.h>

namespace cmcsurf {

std::string check_threads(long long threads) {
  if (threads >= 0 && threads <= kMaxThreads) return {};
  return fmt::format("got {}; accepted: 0 <= T <= {} (0: OMP_NUM_THREADS or all cores)", threads,
                     kMaxThreads);
}

std::string check_seed(long long seed) {
  if (seed >= 0) return {};
  return fmt::format("got {}; accepted: 0 <= S < 2^64", seed);
}

}  // namespace cmcsurf
