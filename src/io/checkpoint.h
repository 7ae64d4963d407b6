// checkpoint.bin: a run's whole state between two time steps (pipeline/cmc.h Checkpoint), so
// that `run --resume DIR` continues it to the same bits (docs/reliability.md).
//
// Container (little-endian; docs/reliability.md has the table):
//   "CMCSCKPT"  u32 format (4)  u32 CRC-32 of the header  u64 header bytes
//   header: CBOR of {version, build, params, outputs, cursor, state, stepper, result,
//                    fields: [{name, n}]}
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

#include "io/build_info.h"
#include "pipeline/cmc.h"

namespace cmcsurf {

inline constexpr const char* kCheckpointFileName = "checkpoint.bin";
inline constexpr int kCheckpointFormat = 4;  // 2: build and outputs in the header; 3: volume_fraction
                                            // per step; 4: euler_characteristic in the measures

// A file that is not a checkpoint this program can continue: what() names the file and the
// problem (truncated, corrupted, another format, program version or build, hostile sizes or
// parameters).
class CheckpointError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct CheckpointFile {
  std::string version;     // of the program that wrote it
  std::string build;       // build_identity() of the program that wrote it
  nlohmann::json params;   // params_json of the run (io/run_report.h), in range
  nlohmann::json outputs;  // what the run writes besides the fields (an object; the caller's)
  Checkpoint checkpoint;   // whole fields (ghost 2 for phi, 1 for the stepper's)
};

// Writes atomically (temporary name, then rename). c's fields must be whole grids (gather
// them first under a decomposition); `outputs` (an object) is kept for the resumed run.
// Throws std::runtime_error on I/O errors.
void write_checkpoint(const std::filesystem::path& path, const nlohmann::json& params,
                      const Checkpoint& c,
                      const nlohmann::json& outputs = nlohmann::json::object());

struct CheckpointReadOptions {
  int max_n = 1 << 13;  // refuse larger grids before allocating
  // The program version and build a checkpoint must come from (empty: any). A run resumes
  // only what the same build wrote: another compiler, flag or commit may take other V-cycles.
  std::string require_version = CMCSURF_VERSION;
  std::string require_build = build_identity();
};

// Reads and checks everything (sizes against the file's before allocating, both checksums,
// finite fields, the parameters' ranges, a cursor on one of the run's grids). Throws
// CheckpointError. Whether a given run can continue it: resume_problem (pipeline/cmc.h).
CheckpointFile read_checkpoint(const std::filesystem::path& path,
                               const CheckpointReadOptions& options = {});
// The same from bytes in memory (`name` stands for the file in messages); for fuzzing.
CheckpointFile parse_checkpoint(std::span<const unsigned char> bytes,
                                const CheckpointReadOptions& options = {},
                                const std::string& name = "<memory>");

}  // namespace cmcsurf
