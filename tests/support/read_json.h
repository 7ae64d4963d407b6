// Test support (not part of the library, which only writes JSON): reading a JSON file back.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

namespace cmcsurf {

// Throws std::runtime_error naming the path on a missing/unreadable file or a parse error
// (with nlohmann's line/column).
nlohmann::json read_json(const std::filesystem::path& path);

}  // namespace cmcsurf
