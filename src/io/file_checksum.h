// CRC-32 (zlib) of a whole file: a cache entry records its field file's and checks it on reuse.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>

namespace cmcsurf {

// nullopt when the file cannot be opened or read to its end.
std::optional<std::uint32_t> file_crc32(const std::filesystem::path& path);

}  // namespace cmcsurf
