// Checkpoints and --resume in the library (docs/reliability.md), one path for `cmcsurf run`,
// `cmcsurf sweep` and the sweep driver: the sink that writes checkpoint.bin while a run goes,
// what an interrupted run leaves, a checkpoint read back and checked against the run that
// continues it, the options a resume may not change, and how a sweep's member starts again.
// Errors a user can cause are OptionError (the command line's exit 2); the command line prints.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "io/checkpoint.h"
#include "io/output_folder.h"
#include "parallel/decomposition.h"
#include "pipeline/cmc.h"
#include "model/run_schema.h"
#include "pipeline/sweep.h"

namespace cmcsurf {

// The default of --checkpoint-every (and Python's sweep(checkpoint_every=)): runs shorter than
// this write none (a signal still does).
constexpr double kDefaultCheckpointEvery = 120.0;

// The RunContext hooks of a run writing into dir: control() asks for a checkpoint every
// `every` seconds and stops when `stop_requested` says so (a signal; one decision for all
// processes under MPI), and checkpoint() writes dir/checkpoint.bin (every process its blocks
// under a decomposition: io/checkpoint.h, format 7). A failed periodic write is passed to
// `warn` once: the run goes on.
class CheckpointSink {
 public:
  // `outputs`: the run's output options, kept in the checkpoint so that --resume writes the
  // folder the uninterrupted run would have written.
  CheckpointSink(std::filesystem::path dir, const RunParams& params, nlohmann::json outputs,
                 double every, std::shared_ptr<const Decomposition> world,
                 std::function<bool()> stop_requested,
                 std::function<void(const std::string&)> warn = {});
  void attach(RunContext& context);
  // The next checkpoints go to another folder, of a run with other parameters (a sweep's
  // members).
  void retarget(std::filesystem::path dir, const RunParams& params);
  // Writes dir/checkpoint.bin now (the interrupted run's state); throws on failure.
  void write(const Checkpoint& c);
  int written() const { return written_; }
  double seconds() const { return seconds_; }  // spent writing checkpoints

 private:
  std::filesystem::path dir_;
  nlohmann::json params_;
  nlohmann::json outputs_;
  double every_;
  std::shared_ptr<const Decomposition> world_;
  std::function<bool()> stop_requested_;
  std::function<void(const std::string&)> warn_;
  double last_ = 0.0;  // steady-clock seconds of the start or the last checkpoint
  int written_ = 0;
  double seconds_ = 0.0;
  bool warned_ = false;
};

// What an interrupted run leaves (rank 0 writes; every process measures): checkpoint.bin,
// history.csv and a report.json marked "stop_reason": "interrupted" with the measures of the
// field so far, `signal` (its name) and how to resume. `failure`: why no checkpoint could be
// written ("" when one was); `root`: this process wrote the report.
struct InterruptedRun {
  std::string failure;
  bool root = true;
};
InterruptedRun write_interrupted_run(const std::filesystem::path& dir, const RunParams& params,
                                     RunInterrupted& stop, CheckpointSink& sink, int threads,
                                     const std::string& resume_command,
                                     const std::string& signal, const nlohmann::json& extra = {});

// dir/checkpoint.bin for `run --resume dir` or a sweep member: read, checked against the run
// that continues it (`entry` with the checkpoint's own parameters, on `world`: resume_problem),
// and, under a decomposition, only this process's blocks of the fields read (collective: the
// processes agree on errors). Any problem is an OptionError naming the file.
struct LoadedCheckpoint {
  nlohmann::json params;   // params_json of the run, in range
  nlohmann::json outputs;  // the output options it was started with (an object)
  std::shared_ptr<const Checkpoint> checkpoint;
};
LoadedCheckpoint load_checkpoint(const std::filesystem::path& dir, RunEntry entry,
                                 const std::shared_ptr<const Decomposition>& world);

// --resume: the run options given (`given_option(o)`) must agree with the parameters the run
// started with (`saved`, params_json), each compared by its key, whatever its CLI name;
// returns the parameters to use. `given` holds the caller's values (defaults where not given);
// `shown(o)` is how a message names the option ("--grid"). Throws OptionError naming `file`.
RunParams resumed_run_params(const RunParams& given, const nlohmann::json& saved,
                             const std::filesystem::path& file,
                             const std::function<bool(const RunOption&)>& given_option,
                             const std::function<std::string(const RunOption&)>& shown);

// sweep --resume DIR and Python's sweep(resume=...): the sweep that DIR/sweep.json describes,
// with its ranges checked as a new sweep's. The caller's `run_params(saved, file)` gives the
// run options (resumed_run_params with its own idea of which were given); the members must
// agree where given. Messages name the arguments as `names` says. Throws OptionError naming
// the file.
struct SweepResumeNames {
  std::string resume = "--resume";
  std::string surfaces = "--surface";
  std::string fractions = "--volume-fractions";
  std::string continuation = "--continuation";
  bool surfaces_given = false;
  bool fractions_given = false;
  bool continuation_given = false;
};
SweepJson resumed_sweep(
    const std::filesystem::path& dir, const SweepParams& given, const SweepResumeNames& names,
    const std::function<RunParams(const nlohmann::json&, const std::filesystem::path&)>&
        run_params);

// How a sweep member's folder starts when a sweep runs into it (decided by the group's rank 0,
// then told to the others): run from scratch (an earlier run's outputs cleared), continue from
// its checkpoint, or keep it complete. kFailed: the folder could not be looked at or claimed
// (`failure` says why). Only a resumed sweep keeps or continues a member.
struct MemberDecision {
  enum class Kind { kRun, kResume, kSkip, kFailed };
  Kind kind = Kind::kRun;
  std::string failure;
  nlohmann::json report;  // kSkip: the member's report.json
};
// On the group's rank 0: claims the member's folder (`claim`, kept by the caller while it
// writes), removes what a killed writer left (`removed`: how many) and decides.
MemberDecision decide_member(const std::filesystem::path& mdir, const SweepMember& m,
                             bool resuming, bool force, FolderClaim& claim, int* removed);
// Rank 0's decision on every process of `group` (collective); the failure text too.
MemberDecision::Kind agree_member_decision(const Decomposition& group, MemberDecision& d);

}  // namespace cmcsurf
