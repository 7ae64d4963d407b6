#include "io/json_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include <fmt/core.h>

#include "io/atomic_file.h"

namespace cmcsurf {

void write_json_atomic(const std::filesystem::path& path, const nlohmann::json& value) {
  std::string text;
  try {
    text = value.dump(2);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(fmt::format("cannot write JSON '{}': {}", path.string(), e.what()));
  }
  text += '\n';
  write_file_atomic(path, text);
}

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
