#include "parallel/agree.h"

#include <exception>
#include <stdexcept>

#include <fmt/core.h>

namespace cmcsurf {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    const std::string what = e.what();
    return what.empty() ? "unknown error" : what;
  }
  return "";
}

void agree_or_throw(const Decomposition* d, const std::string& error) {
  int rank = error.empty() ? -1 : 0;
  const std::string first = d ? d->first_error(error, &rank) : error;
  if (first.empty()) return;
  if (d && d->ranks() > 1)
    throw std::runtime_error(fmt::format("process {} of {}: {}", rank, d->ranks(), first));
  throw std::runtime_error(first);
}

}  // namespace cmcsurf
