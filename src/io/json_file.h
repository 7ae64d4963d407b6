// JSON reports: pretty-printed, written atomically. (Reading them back is test support:
// tests/support/read_json.h.)
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

namespace cmcsurf {

// Indent 2, trailing newline. nlohmann writes NaN and +-inf as null (JSON has
// no literal for them), so a non-finite number reads back as null: store
// such values as strings or leave them out if they must survive. Invalid
// UTF-8 in strings throws std::runtime_error.
void write_json_atomic(const std::filesystem::path& path, const nlohmann::json& value);

}  // namespace cmcsurf
