// JSON reports: pretty-printed, written atomically; reading with errors that
// name the file.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

namespace cmcsurf {

// Indent 2, trailing newline. nlohmann writes NaN and +-inf as null (JSON has
// no literal for them), so a non-finite number reads back as null: store
// such values as strings or leave them out if they must survive. Invalid
// UTF-8 in strings throws std::runtime_error.
void write_json_atomic(const std::filesystem::path& path, const nlohmann::json& value);

// Throws std::runtime_error naming the path on a missing/unreadable file or a
// parse error (with nlohmann's line/column).
nlohmann::json read_json(const std::filesystem::path& path);

}  // namespace cmcsurf
