#include "support/read_json.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include <fmt/core.h>

namespace cmcsurf {

nlohmann::json read_json(const std::filesystem::path& path) {
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int err = errno;
    throw std::runtime_error(fmt::format("cannot open JSON file '{}': {}", path.string(),
                                         err ? std::strerror(err) : "unknown error"));
  }
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw std::runtime_error(fmt::format("invalid JSON in '{}': {}", path.string(), e.what()));
  }
}

}  // namespace cmcsurf
