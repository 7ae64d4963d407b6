// The checkpoint reader (io/checkpoint.h) on arbitrary bytes: it either returns a state whose
// fields are finite whole grids on the cursor's N, or throws CheckpointError. Each input is
// read twice: as it is (the checksums catch almost every mutation), and with both CRC-32s
// recomputed, so that mutations reach the CBOR header and the checks behind the checksums.
#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "fuzz_target.h"
#include "io/checkpoint.h"

namespace {

using cmcsurf::fuzz::Input;
using cmcsurf::fuzz::Outcome;
using cmcsurf::fuzz::require;

// The container's fixed parts (io/checkpoint.h): magic, format, header CRC, header bytes.
constexpr std::size_t kPreamble = 8 + 4 + 4 + 8;
constexpr std::size_t kTrailer = 4 + 8;

std::uint32_t crc32_of(const unsigned char* p, std::size_t n) {
  return std::uint32_t(::crc32_z(0, p, n));
}

// The input with both checksums made to match its bytes; empty when it is too short or its
// header length does not fit.
std::vector<unsigned char> with_valid_checksums(Input input) {
  if (input.size() < kPreamble + kTrailer) return {};
  std::uint64_t header = 0;
  std::memcpy(&header, input.data() + 16, 8);
  if (header > input.size() - kPreamble - kTrailer) return {};
  std::vector<unsigned char> b(input.begin(), input.end());
  const std::uint32_t header_crc = crc32_of(b.data() + kPreamble, header);
  std::memcpy(b.data() + 12, &header_crc, 4);
  const std::size_t data = kPreamble + header;
  const std::uint32_t data_crc = crc32_of(b.data() + data, b.size() - kTrailer - data);
  std::memcpy(b.data() + b.size() - kTrailer, &data_crc, 4);
  return b;
}

Outcome read(Input bytes) {
  cmcsurf::CheckpointReadOptions options;
  options.max_n = 64;
  cmcsurf::CheckpointFile f;
  try {
    f = cmcsurf::parse_checkpoint(bytes, options, "fuzz input");
  } catch (const cmcsurf::CheckpointError&) {
    return Outcome::refused;
  }
  const cmcsurf::Field& phi = f.checkpoint.result.phi;
  require(phi.n() == f.checkpoint.cursor.grid && phi.n() >= 1 && phi.n() <= options.max_n,
          "phi is not on the cursor's grid");
  for (int k = 0; k < phi.n(); ++k)
    for (int j = 0; j < phi.n(); ++j)
      for (int i = 0; i < phi.n(); ++i) require(std::isfinite(phi(i, j, k)), "phi not finite");
  require(cmcsurf::halo_is_current(phi), "phi has stale ghosts");
  return Outcome::parsed;
}

}  // namespace

CMCSURF_FUZZ_TARGET(checkpoint) {
  const std::vector<unsigned char> repaired = with_valid_checksums(input);
  if (!repaired.empty()) read(repaired);  // explores; only its properties are checked
  return read(input);                     // what the corpus names (ok-*, bad-*) promise
}
