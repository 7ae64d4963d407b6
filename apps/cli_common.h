// Shared pieces of the command line: option groups, validation, progress and exit codes.
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "measure/quality.h"

#include "pipeline/cmc.h"
#include "model/run_options.h"
#include "model/run_schema.h"
#include "io/run_folder.h"

namespace cmcsurf::cli {

// Exit codes: 0 done, 1 run failed (divergence, I/O), 2 bad input (nothing written).
constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

// Thrown by validation with a message naming the option and the accepted range.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Options shared by run, sweep and scaffold: every option of the run option table
// (model/run_schema.h). The command line's side of RunChoices: the names given to the choice
// options, and each option's CLI11 handle, whose count says whether it was given.
struct RunOptionStrings {
  RunChoices choices;
  std::vector<std::pair<const RunOption*, const CLI::Option*>> options;
};
// What --fast selects: each table entry's `fast` (model/run_schema.cpp).
void add_run_options(CLI::App& app, RunParams& p, RunOptionStrings& s, bool with_surface);
// One more entry of the table, by key, where a command takes it beside add_run_options's
// (sweep's --structure); not of the solver group.
void add_run_option(CLI::App& app, RunParams& p, RunOptionStrings& s, const std::string& key);
// Converts the names and checks every range (finish_run_params); throws UsageError.
void finish_run_options(RunParams& p, const RunOptionStrings& s, bool check_surface);

// --threads T (T >= 0; 0 keeps OMP_NUM_THREADS or all cores), for every command.
void add_threads_option(CLI::App& app, int& threads);
// Sets the OpenMP thread count (choose_threads: 0 keeps OMP_NUM_THREADS or, without it, all
// cores, under mpirun each rank's share of its binding's cores) and returns the count in use;
// rank 0 warns when an explicit count oversubscribes a node. Collective under mpirun.
int apply_threads(int threads);

// Prints a step line to stderr: in place on a terminal (at most ~10 per second), otherwise a
// line every few seconds and at each new stage.
class Progress {
 public:
  explicit Progress(bool quiet);
  void step(const StepRecord& r);
  void finish();

 private:
  bool quiet_, tty_;
  double last_print_ = -1.0;
  std::string last_stage_;
  bool pending_newline_ = false;
  StepRecord last_;
  bool last_printed_ = true;
  void print(const StepRecord& r, bool new_stage);
};

std::string version_string();

// " +- 2.1e-05" for a finite error estimate, "" otherwise.
std::string plus_minus(double error);

// clear_run_outputs, decomposition_json and write_run_folder: io/run_folder.h.

}  // namespace cmcsurf::cli
