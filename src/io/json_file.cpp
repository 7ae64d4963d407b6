#include "io/json_file.h"

#include <stdexcept>

#include <fmt/core.h>

#include "common/atomic_file.h"

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

}  // namespace cmcsurf
