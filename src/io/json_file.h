// JSON reports: pretty-printed, written atomically; and reading a JSON file a run relies on.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

namespace cmcsurf {

// Indent 2, trailing newline. nlohmann writes NaN and +-inf as null (JSON has
// no literal for them), so a non-finite number reads back as null: store
// such values as strings or leave them out if they must survive. Invalid
// UTF-8 in strings throws std::runtime_error.
void write_json_atomic(const std::filesystem::path& path, const nlohmann::json& value);

// A JSON file a run or resume relies on (sweep.json, a member's report.json, a report given on
// the command line). Throws std::runtime_error starting with the path: a missing or unreadable
// file ("cannot open"), one that is not a regular file, or a parse error (nlohmann's line).
nlohmann::json read_json_file(const std::filesystem::path& path);

}  // namespace cmcsurf
