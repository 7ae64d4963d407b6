// checkpoint.bin: a run's whole state between two time steps (model/run.h Checkpoint), so
// that `run --resume DIR` continues it to the same bits (docs/reliability.md).
//
// Container (little-endian; docs/reliability.md has the table):
//   "CMCSCKPT"  u32 format (6 or 7; 4 or 5 read)  u32 CRC-32 of the header  u64 header bytes
//   header: CBOR of {version, build, params, outputs, cursor, state, stepper, result, anderson,
//                    fields: [{name, n, bytes}], format 7 also pieces: {id, list}}
//   format 6 (whole grids): each array in the header's order: n^3 values (float64, or float32
//     for the mixer's differences), x fastest
//   format 7 (blocks of a decomposed run): no field bytes here
//   u32 CRC-32 of the field bytes  "CKPTDONE"
// CBOR keeps every double exactly, NaN included (an error estimate not computed). Formats 4
// and 5 are 6 and 7 without `anderson` and `bytes` (every array float64, no mixer's).
//
// Format 7 keeps no whole grid anywhere: process R writes its blocks into
// checkpoint.parts/<id>-rRRRRR.bin, where <id> is 16 hex digits drawn anew for each checkpoint:
//   "CMCSCPRT"  u32 format (7)  u64 id  i32 n  i32 offset[3]  i32 size[3]  u32 field count
//   each array in the header's order: size[0] size[1] size[2] values, x fastest
//   u32 CRC-32 of every byte before it  "CKPTDONE"
// and the header's pieces.list gives, in rank order, each piece's file, offset, size and
// CRC-32 (the pieces form a Cartesian grid of boxes that tile the n^3 grid).
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "io/build_info.h"
#include "model/run.h"

namespace cmcsurf {

inline constexpr const char* kCheckpointFileName = "checkpoint.bin";
// 2: build and outputs in the header; 3: volume_fraction per step; 4: euler_characteristic in
// the measures; 6: the Anderson mixer's history (header `anderson`, its arrays after the fields,
// each listed with its bytes per value). Formats 4 and 5 are still read: a run continued from
// one starts its mixing afresh (Checkpoint::anderson_carried).
inline constexpr int kCheckpointFormat = 6;
inline constexpr int kCheckpointFormatNoMixer = 4;
// The same header with the fields in one piece file per process (the layout above).
inline constexpr int kCheckpointPiecesFormat = 7;
inline constexpr int kCheckpointPiecesFormatNoMixer = 5;

// The folder of a checkpoint's pieces: DIR/checkpoint.parts for DIR/checkpoint.bin.
std::filesystem::path checkpoint_piece_dir(const std::filesystem::path& path);
// Removes a checkpoint: the file first (so that none points at missing pieces), then its
// pieces' folder. Missing files are fine; other errors throw std::runtime_error naming them.
void remove_checkpoint(const std::filesystem::path& path);

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

// Writes atomically (temporary name, then rename); `outputs` (an object) is kept for the
// resumed run. Whole-grid fields give format 6 (one file), unless in_pieces. Blocks of a
// decomposed grid give format 7, collectively: every process of the decomposition calls it
// with its blocks (rank 0's header is written; every process's c.result but phi is the same),
// writes its piece, and, once every piece is in place, rank 0 renames the new checkpoint.bin
// into place and then removes the pieces of the one it replaced. Until that rename the earlier
// checkpoint stays whole. Throws std::runtime_error on I/O errors, on every process alike
// ("process R of P: ..."), after removing the pieces it wrote.
void write_checkpoint(const std::filesystem::path& path, const nlohmann::json& params,
                      const Checkpoint& c,
                      const nlohmann::json& outputs = nlohmann::json::object(),
                      bool in_pieces = false);

// A step of the history as the header keeps it: history.csv's columns by name. A step written
// before the equilibrium_residual column existed reads it as NaN (the rule's "not measured").
void to_json(nlohmann::json& j, const StepRecord& r);
void from_json(const nlohmann::json& j, StepRecord& r);

struct CheckpointReadOptions {
  int max_n = 1 << 13;  // refuse larger grids before allocating
  // The program version and build a checkpoint must come from (empty: any). A run resumes
  // only what the same build wrote: another compiler, flag or commit may take other V-cycles.
  std::string require_version = CMCSURF_VERSION;
  std::string require_build = build_identity();
  // Null or one process: whole fields. Otherwise this process's blocks of the cursor's grid:
  // only the parts of the file (format 6) or the pieces (format 7) that hold them are kept,
  // every byte read is checked as for whole fields, and the ghosts are not written (not
  // collective: agree on errors, then exchange the halos). If the decomposition does not split
  // that grid the fields are left empty and unread (resume_problem says why).
  std::shared_ptr<const Decomposition> decomposition;
};

// Reads and checks everything (sizes against the file's before allocating, both checksums,
// finite fields, the parameters' ranges, a cursor on one of the run's grids; format 7: the
// pieces' list and tiling, and each piece read: its size, id, box, CRC-32 against its own and
// the header's). Throws CheckpointError. Whether a given run can continue it: resume_problem
// (pipeline/cmc.h).
CheckpointFile read_checkpoint(const std::filesystem::path& path,
                               const CheckpointReadOptions& options = {});
// The same from bytes in memory (`name` stands for the file in messages); for fuzzing. Format
// 5 is refused there (its pieces are files).
CheckpointFile parse_checkpoint(std::span<const unsigned char> bytes,
                                const CheckpointReadOptions& options = {},
                                const std::string& name = "<memory>");

}  // namespace cmcsurf
