#include "io/file_checksum.h"

#include <zlib.h>

#include <fstream>
#include <vector>

namespace cmcsurf {

std::optional<std::uint32_t> file_crc32(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::vector<char> buffer(1 << 20);
  uLong crc = ::crc32(0L, Z_NULL, 0);
  while (in) {
    in.read(buffer.data(), std::streamsize(buffer.size()));
    const std::streamsize got = in.gcount();
    if (got > 0)
      crc = ::crc32_z(crc, reinterpret_cast<const Bytef*>(buffer.data()), std::size_t(got));
  }
  if (in.bad() || !in.eof()) return std::nullopt;
  return std::uint32_t(crc);
}

}  // namespace cmcsurf
