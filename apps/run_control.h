// Long runs survive interruption (docs/reliability.md): SIGINT/SIGTERM stop a run between two
// time steps with a checkpoint, periodic checkpoints bound the work a crash loses, and
// --resume continues either to the same bits.
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_common.h"
#include "io/checkpoint.h"
#include "io/json_file.h"  // read_json_file, which the commands call
#include "io/output_folder.h"
#include "io/run_report.h"
#include "parallel/decomposition.h"
#include "pipeline/cmc.h"
#include "pipeline/run_resume.h"

namespace cmcsurf::cli {

// Installs the SIGINT/SIGTERM handlers for its lifetime: the first signal asks the run to stop
// after its current step; a second one exits at once with 128 + signal.
class SignalGuard {
 public:
  SignalGuard();
  ~SignalGuard();
  SignalGuard(const SignalGuard&) = delete;
  SignalGuard& operator=(const SignalGuard&) = delete;
  // The signal received (0: none yet).
  static int received();
  // 130 for SIGINT, 143 for SIGTERM.
  static int exit_code() { return 128 + received(); }
};


struct CheckpointOptions {
  double every = kDefaultCheckpointEvery;  // seconds; 0: no periodic checkpoints
  std::string resume;                      // run --resume DIR
};
void add_checkpoint_options(CLI::App& app, CheckpointOptions& options, bool with_resume);

// A CheckpointSink (pipeline/run_resume.h) that stops on SIGINT/SIGTERM and warns on stderr.
CheckpointSink signal_checkpoint_sink(std::filesystem::path dir, const RunParams& params,
                                      nlohmann::json outputs, double every,
                                      std::shared_ptr<const Decomposition> world);

// Calls f, turning the library's OptionError (model/run_options.h) into a UsageError.
template <class F>
auto as_usage(F&& f) {
  try {
    return f();
  } catch (const OptionError& e) {
    throw UsageError(e.what());
  }
}

// What an interrupted run leaves (write_interrupted_run, pipeline/run_resume.h), said as
// print_interrupted says it; returns the exit code.
int finish_interrupted(const std::filesystem::path& dir, const RunParams& params,
                       RunInterrupted& stop, CheckpointSink& sink, int threads,
                       const std::string& resume_command, bool quiet,
                       const nlohmann::json& extra = {});

// The name of the signal received, as an interrupted report.json names it.
std::string stop_signal_name();

// What an interrupted run left, said on stderr (the error when no checkpoint was written);
// returns the exit code.
int print_interrupted(const std::filesystem::path& dir, const Checkpoint& c,
                      const InterruptedRun& left, const std::string& resume_command, bool quiet);

// Output options kept for a resume (a checkpoint's or sweep.json's "outputs"): each one the
// command line did not give takes the saved value. `restore(option, key, value)` does one;
// a saved value of the wrong type is a UsageError naming `file`.
class OutputRestorer {
 public:
  OutputRestorer(const CLI::App& app, const nlohmann::json& saved, std::filesystem::path file)
      : app_(app), saved_(saved), file_(std::move(file)) {}
  template <class T>
  void restore(const char* option, const char* key, T& value) const {
    if (app_.count(option) > 0 || !saved_.contains(key)) return;
    try {
      value = json_value<T>(saved_.at(key), key);  // in T's range, never wrapped
    } catch (const std::runtime_error&) {
      throw_bad(key);
    }
  }

 private:
  [[noreturn]] void throw_bad(const char* key) const;
  const CLI::App& app_;
  const nlohmann::json& saved_;
  std::filesystem::path file_;
};

// Claims an output folder (io/output_folder.h) on the world's rank 0, before any work; every
// process learns of a refusal (collective): a UsageError for a wrong choice of folder (exit 2),
// std::runtime_error when another writer holds it or it cannot be written (exit 1). Other
// processes get an empty claim.
FolderClaim claim_folder(const std::filesystem::path& dir, const ClaimOptions& options,
                         const Decomposition& world);

// A CLI11 check refusing "" (an option given with an empty value is an error, never ignored).
std::function<std::string(const std::string&)> non_empty_text();

// Refuses (UsageError, on every process alike: collective) a run whose memory estimate does
// not fit what some process may still take (model/run_options.h, check_run_memory).
// `ranks`: the processes one run is split over (0: all of world's).
void refuse_if_too_large(const RunParams& p, const Decomposition& world, int ranks = 0);

// --force for run and sweep: write into a non-empty folder that cmcsurf did not write.
void add_force_option(CLI::App& app, bool& force);

// A command line a user can paste into a POSIX shell: each word single-quoted where needed.
std::string shell_quote(const std::string& word);

// Removes what a writer killed before its commit left in dir (common/atomic_file.h), saying so.
void remove_leftover_temporaries(const std::filesystem::path& dir, bool quiet);

// This executable's path (for the resume command printed on interruption).
std::string self_executable();

// --resume: the run options given on the command line (`options`, add_run_options's) must agree
// with the parameters the run started with (`saved`, params_json), each compared by its key;
// returns the parameters to use. `given` is the command line's own result (defaults where not
// given).
RunParams resumed_params(const RunOptionStrings& options, const RunParams& given,
                         const nlohmann::json& saved, const std::filesystem::path& file);

}  // namespace cmcsurf::cli
