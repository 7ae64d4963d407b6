#include "model/option_checks.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

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

std::string check_omp_num_threads(const char* value) {
  if (value == nullptr) return {};
  const std::string text = value;
  bool ok = true;
  std::size_t pos = 0;
  do {  // one count per comma-separated item
    const std::size_t end = std::min(text.find(',', pos), text.size());
    std::size_t a = pos, b = end;
    while (a < b && std::isspace(static_cast<unsigned char>(text[a]))) ++a;
    while (b > a && std::isspace(static_cast<unsigned char>(text[b - 1]))) --b;
    long long count = 0;
    ok = a < b && b - a <= 5;
    for (std::size_t c = a; ok && c < b; ++c) {
      ok = std::isdigit(static_cast<unsigned char>(text[c])) != 0;
      count = 10 * count + (text[c] - '0');
    }
    ok = ok && count >= 1 && count <= kMaxThreads;
    pos = end + 1;
  } while (ok && pos <= text.size());
  if (ok) return {};
  return fmt::format("got '{}'; accepted: 1 <= T <= {}, or a comma list of such counts (one per "
                     "nesting level); unset: all cores",
                     text, kMaxThreads);
}

}  // namespace cmcsurf
