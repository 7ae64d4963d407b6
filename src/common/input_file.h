// Files cmcsurf reads from a path a user gave (checkpoint.bin, field.vti, .pvti pieces,
// report.json, sweep.json, an STL): checked before they are opened.
#pragma once

#include <filesystem>
#include <string>

namespace cmcsurf {

// Throws std::runtime_error "<what> '<path>' is not a regular file (<kind>)" when `path`
// exists and is not a regular file after following links: a FIFO would block the open (a hang),
// a directory, device or socket would read as garbage or never end. A missing path passes:
// the caller's own open reports it.
void require_regular_file(const std::filesystem::path& path, const std::string& what);

// The whole file at `path`, checked by require_regular_file(path, what) first; throws
// std::runtime_error "cannot read '<path>'" when it cannot be opened or read.
std::string read_input_file(const std::filesystem::path& path, const std::string& what);

}  // namespace cmcsurf
