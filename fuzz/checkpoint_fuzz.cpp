// The checkpoint reader (io/checkpoint.h) on arbitrary bytes: it either returns a state whose
// fields are finite whole grids on the cursor's N and whose parameters pass the command line's
// checks, or throws CheckpointError. Each input is read twice: as it is (the checksums catch
// almost every mutation), and with both CRC-32s recomputed, so that mutations reach the CBOR
// header and the checks behind the checksums. A state the reader returns then goes through
// resume_problem (pipeline/cmc.h) for both ways `run`/`sweep --resume` continue a checkpoint,
// and where that accepts it, through the run's restore up to its first time step (stopped
// there by its control), which must give back the same position. `parsed` means that one of
// the two accepted it: a bad-* seed must be refused by the reader or by both.
#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "fuzz_target.h"
#include "io/checkpoint.h"
#include "io/run_report.h"
#include "pipeline/cmc.h"

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

// Continues the checkpoint as `entry` would and stops before the first time step: the run
// must stop there (no step taken) at the checkpoint's own position, with its phi.
bool restore_and_stop(const cmcsurf::CheckpointFile& f, cmcsurf::RunEntry entry) {
  using namespace cmcsurf;
  const RunParams params = params_from_json(f.params);
  const Checkpoint& c = f.checkpoint;
  if (!resume_problem(c, params, entry).empty()) return false;  // run_cmc would throw
  RunContext context;
  context.resume = std::make_shared<const Checkpoint>(c);
  context.control = [] { return RunControl::kStop; };
  try {
    if (entry == RunEntry::kCmc)
      run_cmc(params, context);
    else
      relax_to_volume_fraction(Field(), params, context);
  } catch (RunInterrupted& stop) {
    const Checkpoint& s = stop.checkpoint;
    require(s.step == c.step && s.cursor.grid == c.cursor.grid &&
                s.cursor.stage == c.cursor.stage && s.cursor.stage_steps == c.cursor.stage_steps,
            "a restored run stopped elsewhere than its checkpoint");
    const Field& a = s.result.phi;
    const Field& b = c.result.phi;
    for (int k = 0; k < b.n(); ++k)
      for (int j = 0; j < b.n(); ++j)
        for (int i = 0; i < b.n(); ++i)
          require(a(i, j, k) == b(i, j, k), "a restored run changed phi before its first step");
    return true;
  }
  require(false, "a restored run took steps (or finished) without asking its control");
  return false;
}

Outcome read(Input bytes) {
  cmcsurf::CheckpointReadOptions options;
  options.max_n = 64;
  options.require_build.clear();  // the seeds outlive the build that wrote them
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
  try {
    cmcsurf::params_from_json(f.params);
  } catch (const std::runtime_error&) {
    require(false, "the reader returned parameters that params_from_json refuses");
  }
  const bool as_run = restore_and_stop(f, cmcsurf::RunEntry::kCmc);
  const bool as_member = restore_and_stop(f, cmcsurf::RunEntry::kRelaxToVolume);
  return as_run || as_member ? Outcome::parsed : Outcome::refused;
}

}  // namespace

CMCSURF_FUZZ_TARGET(checkpoint) {
  const std::vector<unsigned char> repaired = with_valid_checksums(input);
  if (!repaired.empty()) read(repaired);  // explores; only its properties are checked
  return read(input);                     // what the corpus names (ok-*, bad-*) promise
}
