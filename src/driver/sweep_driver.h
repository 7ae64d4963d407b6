// The sweep driver (`cmcsurf sweep` and its resume; docs/families.md, docs/scaling.md): the
// members of a sweep run into one folder, one process or groups of processes under mpirun,
// each member's folder finished as `run` finishes its own (driver/run_finish.h), with
// sweep.csv, sweep.json, families.png, gallery.png, the properties chart and report.html.
// The command line parses and prints (apps/cmd_sweep.cpp): what happens reaches it through
// SweepHooks. Errors a user can cause are OptionError; the driver's outcome is an exit code
// as the command line's (0 done, 1 failed, 2 bad input, 128 + signal interrupted).
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "parallel/decomposition.h"
#include "driver/run_finish.h"
#include "pipeline/run_resume.h"
#include "pipeline/sweep.h"

namespace cmcsurf {

// How the processes share the sweep (docs/scaling.md, "Sweeps across nodes"): `groups` groups
// of `group_ranks`, and the group of each member. One group of one process without mpirun.
struct GroupPlan {
  int groups = 1;
  int group_ranks = 1;
  std::vector<int> member_group;
};
// --groups (0: automatic), checked alike on every process before any communication; an
// OptionError names --groups and the accepted divisors.
GroupPlan plan_groups(int groups, const SweepParams& sp, const Decomposition& world);
// The plan in words, for the command line to print.
std::string describe_plan(const SweepParams& sp, const GroupPlan& plan, const Decomposition& group);

// The folder name of member `index` (surfaces outermost).
std::string member_name_at(const SweepParams& sp, int index);

// sweep.json: what the sweep was (per-member parameters are in each report.json); `outputs`:
// the output options a resume restores.
nlohmann::json sweep_summary(const SweepParams& sp, const nlohmann::json& outputs,
                             std::size_t members, int threads, double wall);

struct SweepJob {
  SweepParams sweep;
  std::filesystem::path dir;
  bool resuming = false;   // sweep --resume: complete members kept, interrupted ones continued
  bool force = false;      // --force
  GroupPlan plan;
  RunFolderOptions member;         // each member's folder (threads, float32, properties)
  bool preview = true;             // preview.png per member and gallery.png
  bool page = true;                // report.html per member and the sweep's
  bool figures = true;   // families.png/.svg, the properties chart (--no-plot: false)
  bool diffuse = false;  // families.png: the diffuse layer's values beside the sharp
  nlohmann::json outputs;          // sweep.json's "outputs" and each checkpoint's
  double checkpoint_every = 0.0;   // seconds; 0: none
  std::string resume_command;      // printed and kept in an interrupted member's report.json
};

// What the command line does with the sweep's events (all optional; called on world rank 0
// unless said otherwise).
struct SweepHooks {
  // Text to print as it is (lines with their newline): `note` unless quiet, `notice` and
  // `error` (why the sweep or a group stopped) always, on the process that says it.
  std::function<void(const std::string&)> note;
  std::function<void(const std::string&)> notice;
  std::function<void(const std::string&)> error;
  std::function<void(const SweepMember&)> starting;
  std::function<void(const SweepMember&, const Checkpoint&)> resuming;
  // A complete member a resumed sweep keeps, with its report.json.
  std::function<void(const SweepMember&, const nlohmann::json& report)> kept;
  // A member this process's group ran, finished (its report.json written).
  std::function<void(const SweepMember&, const nlohmann::json& report)> finished;
  // The same member's result and quality stage, for a caller that keeps them (Python's
  // sweep(out=...) returns them as the in-memory sweep does); on the group's writer.
  std::function<void(const SweepMember&, const RunResult&, const CmcQuality&,
                     const nlohmann::json& report)>
      result;
  // A member another group ran, from its report.json.
  std::function<void(const nlohmann::json& report, int index, int count, int group)> gathered;
  std::function<void(const StepRecord&)> step;  // every process; the command line's Progress
  std::function<void()> steps_done;
  std::function<bool()> stop_requested;  // a signal: stop after this step or member
  std::function<int()> stop_code;        // its exit code (128 + signal)
  std::function<std::string()> signal_name;
  // An interrupted member's folder was left with its checkpoint (every process of its group).
  std::function<void(const std::filesystem::path&, const Checkpoint&, const InterruptedRun&)>
      interrupted;
  std::function<void(const std::string&)> warning;  // CheckpointSink's, every process
};

struct SweepOutcome {
  int exit_code = 0;
  std::size_t members = 0;  // rows in sweep.csv
  double wall_seconds = 0.0;
  bool families_figure = false;  // families.png written
};

// sweep.json's "outputs" (and each member checkpoint's) of `job`: what the sweep writes besides
// the members' fields, so that a resume alone writes the folder the uninterrupted sweep would
// have. `porosity`: --properties-porosity as given ("": none). Never a program to run: a data
// file that someone else may have written restores options, it never chooses an executable.
nlohmann::json sweep_outputs_json(const SweepJob& job, const std::string& porosity);

// Runs the sweep into job.dir (claimed by the caller), collective over the world's processes.
// Setup problems (the folder) end every process with 1 before any member runs.
SweepOutcome drive_sweep(const SweepJob& job, const SweepHooks& hooks);

}  // namespace cmcsurf
