#include "io/file_checksum.h"

#include <gtest/gtest.h>

#include <fstream>

namespace cmcsurf {
namespace {

TEST(FileChecksum, Crc32OfKnownBytesAndAMissingFile) {
  const auto path = std::filesystem::temp_directory_path() / "cmcsurf_file_checksum_test.txt";
  std::ofstream(path, std::ios::binary) << "123456789";
  // The CRC-32 check value of "123456789" (ISO-HDLC, as zlib's crc32).
  EXPECT_EQ(file_crc32(path), std::optional<std::uint32_t>(0xCBF43926u));
  std::ofstream(path, std::ios::binary) << "123456788";
  EXPECT_NE(file_crc32(path), std::optional<std::uint32_t>(0xCBF43926u));
  std::filesystem::remove(path);
  EXPECT_EQ(file_crc32(path), std::nullopt);
}

}  // namespace
}  // namespace cmcsurf
