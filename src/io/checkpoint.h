// checkpoint.bin: a run's whole state between two time steps (pipeline/cmc.h Checkpoint), so
// that `run --resume DIR` continues it to the same bits (docs/reliability.md).
//
// Container (little-endian; docs/reliability.md has the table):
//   "CMCSCKPT"  u32 format (1)  u32 CRC-32 of the header  u64 header bytes
//   header: CBOR of {version, params, cursor, state, stepper, result, fields: [{name, n}]}
//   each field in the header's order: n^3 float64, x fastest (the interior; whole grid)
//   u32 CRC-32 of the field bytes  "CKPTDONE"
// CBOR keeps every double exactly, NaN included (an error estimate not computed).
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "pipeline/cmc.h"

namespace cmcsurf {

inline constexpr const char* kCheckpointFileName = "checkpoint.bin";
inline constexpr int kCheckpointFormat = 1;

// A file that is not a checkpoint this program can continue: what() names the file and the
// problem (truncated, corrupted, another format or program version, hostile sizes).
class CheckpointError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct CheckpointFile {
  std::string version;     // of the program that wrote it
  nlohmann::json params;   // params_json of the run (io/run_report.h)
  Checkpoint checkpoint;   // whole fields (ghost 2 for phi, 1 for the stepper's)
};

// Writes atomically (temporary name, then rename). c's fields must be whole grids (gather
// them first under a decomposition). Throws std::runtime_error on I/O errors.
void write_checkpoint(const std::filesystem::path& path, const nlohmann::json& params,
                      const Checkpoint& c);

struct CheckpointReadOptions {
  int max_n = 1 << 13;  // refuse larger grids before allocating
  // The program version a checkpoint must come from (empty: any). A run resumes only what the
  // same version wrote: another build may take other V-cycles.
  std::string require_version = CMCSURF_VERSION;
};

// Reads and checks everything (sizes against the file's before allocating, both checksums,
// finite fields, a consistent cursor). Throws CheckpointError.
CheckpointFile read_checkpoint(const std::filesystem::path& path,
                               const CheckpointReadOptions& options = {});
// The same from bytes in memory (`name` stands for the file in messages); for fuzzing.
CheckpointFile parse_checkpoint(std::span<const unsigned char> bytes,
                                const CheckpointReadOptions& options = {},
                                const std::string& name = "<memory>");

}  // namespace cmcsurf
