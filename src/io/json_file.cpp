#include "io/json_file.h"

#include <fstream>
#include <stdexcept>

#include <fmt/core.h>

#include "common/atomic_file.h"
#include "common/input_file.h"

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

nlohmann::json read_json_file(const std::filesystem::path& path) {
  require_regular_file(path, "JSON file");
  std::ifstream in(path);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open", path.string()));
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(fmt::format("{}: not valid JSON: {}", path.string(), e.what()));
  }
}

}  // namespace cmcsurf
