#include "run_control.h"

#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstring>
#include <fstream>
#include <iostream>

#include <fmt/format.h>

#include "cli_common.h"
#include "common/atomic_file.h"
#include "common/input_file.h"
#include "io/json_file.h"
#include "io/run_report.h"

namespace cmcsurf::cli {

namespace {

namespace fs = std::filesystem;

volatile std::sig_atomic_t g_signal = 0;

extern "C" void on_stop_signal(int sig) {
  if (g_signal != 0) _exit(128 + sig);  // the second signal: at once
  g_signal = sig;
  static const char note[] =
      "\ncmcsurf: stopping after this time step to write a checkpoint (signal again to exit "
      "at once)\n";
  [[maybe_unused]] const ssize_t w = ::write(STDERR_FILENO, note, sizeof note - 1);
}

struct sigaction g_previous[2];
constexpr int kSignals[2] = {SIGINT, SIGTERM};

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

const char* signal_name(int sig) {
  return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "a signal";
}

}  // namespace

SignalGuard::SignalGuard() {
  g_signal = 0;
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;
  for (int i = 0; i < 2; ++i) sigaction(kSignals[i], &sa, &g_previous[i]);
}

SignalGuard::~SignalGuard() {
  for (int i = 0; i < 2; ++i) sigaction(kSignals[i], &g_previous[i], nullptr);
}

int SignalGuard::received() { return int(g_signal); }

std::function<std::string(const std::string&)> non_empty_text() {
  return [](const std::string& text) -> std::string {
    return text.empty() ? "an empty value; accepted: a non-empty name" : "";
  };
}

void add_checkpoint_options(CLI::App& app, CheckpointOptions& options, bool with_resume) {
  app.add_option("--checkpoint-every", options.every,
                 fmt::format("Write checkpoint.bin into the output folder every SECONDS of the "
                             "solve, so that a crash loses at most that much (0: none; runs "
                             "shorter than the interval write none, and SIGINT/SIGTERM always "
                             "write one). Removed when the run completes"))
      ->capture_default_str()
      ->check(
          [](const std::string& text) -> std::string {
            char* end = nullptr;
            const double v = std::strtod(text.c_str(), &end);
            if (text.empty() || *end != '\0') return {};  // left to CLI11's conversion
            return v >= 0.0 && v <= 1e9 ? "" : fmt::format("got {}; accepted: 0 to 1e9", text);
          },
          "0 <= SECONDS <= 1e9");
  if (with_resume)
    app.add_option("--resume", options.resume,
                   "Continue the interrupted run in DIR from DIR/checkpoint.bin, to the same "
                   "result as if it had not stopped; its parameters come from the checkpoint "
                   "(options given must agree with them). A sweep skips its complete members "
                   "and resumes the interrupted one")
        ->check(non_empty_text(), "DIR");
}

CheckpointSink::CheckpointSink(fs::path dir, const RunParams& params, nlohmann::json outputs,
                               double every, std::shared_ptr<const Decomposition> world)
    : dir_(std::move(dir)),
      params_(params_json(params)),
      outputs_(std::move(outputs)),
      every_(every),
      world_(std::move(world)),
      last_(now_seconds()) {}

void CheckpointSink::attach(RunContext& context) {
  context.control = [this] {
    int code = g_signal != 0 ? 2 : (every_ > 0.0 && now_seconds() - last_ >= every_ ? 1 : 0);
    if (world_ && world_->distributed()) code = int(world_->max(double(code)));  // one decision
    return code == 2 ? RunControl::kStop : code == 1 ? RunControl::kCheckpoint
                                                     : RunControl::kContinue;
  };
  context.checkpoint = [this](const Checkpoint& c) {
    try {
      write(c);
    } catch (const std::exception& e) {
      if (!warned_)
        std::cerr << fmt::format("\nwarning: no checkpoint written ({}); the run goes on\n",
                                 e.what());
      warned_ = true;
    }
    last_ = now_seconds();
  };
}

void CheckpointSink::retarget(fs::path dir, const RunParams& params) {
  dir_ = std::move(dir);
  params_ = params_json(params);
}

std::string self_executable() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? "cmcsurf" : exe.string();
}

nlohmann::json read_json_file(const fs::path& path) {
  require_regular_file(path, "JSON file");
  std::ifstream in(path);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open", path.string()));
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(fmt::format("{}: not valid JSON: {}", path.string(), e.what()));
  }
}

void CheckpointSink::write(const Checkpoint& c) {
  const double t0 = now_seconds();
  if (world_ && world_->distributed() && !c.result.phi.decomposition()) {
    // Fields every process holds whole (a grid the run does not split): rank 0 writes them.
    if (world_->rank() == 0) write_checkpoint(dir_ / kCheckpointFileName, params_, c, outputs_);
  } else {
    // Whole grids: one file (format 4); blocks: every process writes its own piece (format 5,
    // collective), so that no process holds the whole grid (io/checkpoint.h).
    write_checkpoint(dir_ / kCheckpointFileName, params_, c, outputs_);
  }
  ++written_;
  seconds_ += now_seconds() - t0;
}

int finish_interrupted(const fs::path& dir, const RunParams& params, RunInterrupted& stop,
                       CheckpointSink& sink, int threads, const std::string& resume_command,
                       bool quiet, const nlohmann::json& extra) {
  Checkpoint& c = stop.checkpoint;
  const bool root = !c.result.phi.decomposition() || c.result.phi.decomposition()->rank() == 0;
  std::string failed;
  try {
    sink.write(c);
  } catch (const std::exception& e) {
    failed = e.what();
  }
  // The report of the field so far (on the stage's grid, which is coarser than --grid while
  // a continuation works on a coarse level).
  RunResult& r = c.result;
  r.final = measure_field(r.phi, params.epsilon);
  r.stop_reason = "interrupted";
  r.converged = false;
  if (root) {
    nlohmann::json report = run_report(params, r, threads);
    report["stop_reason"] = "interrupted";
    report["checkpoint"] = {{"file", failed.empty() ? kCheckpointFileName : ""},
                            {"step", c.step},
                            {"stage", c.cursor.stage},
                            {"grid", c.cursor.grid},
                            {"signal", signal_name(SignalGuard::received())}};
    report["checkpoints_written"] = sink.written();
    report["checkpoint_seconds"] = sink.seconds();
    report["resume"] = resume_command;
    for (const auto& [key, value] : extra.items()) report[key] = value;
    write_history_csv(dir / "history.csv", r.history);
    write_json_atomic(dir / "report.json", report);
  }
  if (!failed.empty()) {
    std::cerr << fmt::format("\nerror: interrupted at step {}, but no checkpoint was written: {}\n",
                             c.step, failed);
    return kExitFailure;
  }
  if (root && !quiet)
    std::cerr << fmt::format(
        "\ninterrupted by {} before step {} ({} on {}^3, {:.1f} s of work kept in {})\n"
        "resume with: {}\n",
        signal_name(SignalGuard::received()), c.step + 1, c.cursor.stage, c.cursor.grid,
        c.elapsed, (dir / kCheckpointFileName).string(), resume_command);
  return SignalGuard::exit_code();
}

LoadedCheckpoint load_checkpoint(const fs::path& dir, RunEntry entry,
                                 const std::shared_ptr<const Decomposition>& world) {
  const fs::path file = dir / kCheckpointFileName;
  // Under a decomposition every process reads only its blocks (of the file, or of the pieces
  // that hold them), so the processes may see different errors: they agree on the first.
  const bool split = world && world->distributed();
  CheckpointReadOptions options;
  if (split) options.decomposition = world;
  CheckpointFile f;
  std::string error;
  try {
    f = read_checkpoint(file, options);
  } catch (const CheckpointError& e) {
    error = e.what();
  }
  if (split) error = world->first_error(error);
  if (!error.empty()) throw UsageError(fmt::format("--resume: {}", error));
  // The run of these parameters must pass through the checkpoint's grid and stage, on this
  // many processes (the fields are empty where that grid does not split).
  const std::string problem = resume_problem(f.checkpoint, params_from_json(f.params), entry,
                                             split ? world.get() : nullptr);
  if (!problem.empty())
    throw UsageError(fmt::format("--resume: {}: a run with its parameters cannot continue it{}: {}",
                                 file.string(),
                                 split ? fmt::format(" on {} processes", world->ranks()) : "",
                                 problem));
  LoadedCheckpoint loaded{std::move(f.params), std::move(f.outputs), nullptr};
  auto c = std::make_shared<Checkpoint>(std::move(f.checkpoint));
  if (split) {  // the blocks were read interior only
    for (Field* x : {&c->result.phi, &c->stepper.nu, &c->stepper.prev_phi, &c->stepper.prev_nu})
      if (x->n() != 0) x->exchange_halo();
  }
  loaded.checkpoint = std::move(c);
  return loaded;
}

void OutputRestorer::throw_bad(const char* key) const {
  throw UsageError(fmt::format("--resume: {}: output option '{}' is {}, not a value of its "
                               "type",
                               file_.string(), key, saved_.at(key).dump()));
}

FolderClaim claim_folder(const fs::path& dir, const ClaimOptions& options,
                         const Decomposition& world) {
  FolderClaim claim;
  std::string error;
  int code = 0;
  if (world.rank() == 0) {
    try {
      claim = claim_output_folder(dir, options);
    } catch (const FolderRefused& e) {
      error = e.what();
      code = e.usage() ? kExitUsage : kExitFailure;
    }
  }
  if (world.distributed()) {
    code = world.max_exit_code(code);
    error = world.first_error(error);
  }
  if (code == kExitUsage) throw UsageError(error);
  if (code != 0) throw std::runtime_error(error);
  return claim;
}

void refuse_if_too_large(const RunParams& p, const Decomposition& world, int ranks) {
  std::string why = check_run_memory(p, ranks > 0 ? ranks : world.ranks());
  if (world.distributed()) why = world.first_error(why);
  if (!why.empty()) throw UsageError(why);
}

void add_force_option(CLI::App& app, bool& force) {
  app.add_flag("--force", force,
               "Write into a non-empty folder that cmcsurf did not write (its files with "
               "cmcsurf's output names are replaced); without it such a folder is refused");
}

std::string shell_quote(const std::string& word) {
  const bool plain = !word.empty() && word.find_first_not_of(
                                          "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                          "0123456789_-+=./:,@%") == std::string::npos;
  if (plain) return word;
  std::string quoted = "'";
  for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

void remove_leftover_temporaries(const fs::path& dir, bool quiet) {
  const int removed = remove_stale_temporaries(dir);
  if (removed > 0 && !quiet)
    std::cerr << fmt::format("removed {} unfinished temporary file(s) an earlier process left "
                             "in {}\n",
                             removed, dir.string());
}

RunParams resumed_params(const RunOptionStrings& options, const RunParams& given,
                         const nlohmann::json& saved, const fs::path& file) {
  RunParams p;
  try {
    p = params_from_json(saved);
  } catch (const std::exception& e) {
    throw UsageError(fmt::format("--resume: {}: {}", file.string(), e.what()));
  }
  // Every option add_run_options made, compared by its key (whatever its CLI name).
  auto cli = [&](const RunOption& o) -> const CLI::Option* {
    for (const auto& [entry, option] : options.options)
      if (entry == &o) return option;
    return nullptr;
  };
  const RunOption* o = changed_run_option(given, p, [&](const RunOption& e) {
    return cli(e) != nullptr && cli(e)->count() > 0;
  });
  if (o != nullptr) {
    const nlohmann::json mine = params_json(given), theirs = params_json(p);
    throw UsageError(fmt::format(
        "--{} {}: {} was written by a run with {} {}; a resumed run keeps the parameters it "
        "started with (leave the option out, or start a new run with another --out)",
        cli(*o)->get_lnames().front(), mine[o->key].dump(), file.string(), o->key,
        theirs[o->key].dump()));
  }
  return p;
}

}  // namespace cmcsurf::cli
