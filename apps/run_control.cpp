#include "run_control.h"

#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstring>
#include <fstream>
#include <iostream>

#include <fmt/format.h>

#include "cli_common.h"
#include "io/atomic_file.h"
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

// A whole-grid copy of a (possibly decomposed) field, on rank 0; the field itself when whole.
Field gathered(const Field& f, int ghost) {
  Field whole(f.n(), ghost);
  gather_field(f, whole, false);
  return whole;
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

void add_checkpoint_options(CLI::App& app, CheckpointOptions& options, bool with_resume) {
  app.add_option("--checkpoint-every", options.every,
                 fmt::format("Write checkpoint.bin into the output folder every SECONDS of the "
                             "solve, so that a crash loses at most that much (0: none; runs "
                             "shorter than the interval write none, and SIGINT/SIGTERM always "
                             "write one). Removed when the run completes"))
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1e9));
  if (with_resume)
    app.add_option("--resume", options.resume,
                   "Continue the interrupted run in DIR from DIR/checkpoint.bin, to the same "
                   "result as if it had not stopped; its parameters come from the checkpoint "
                   "(options given must agree with them). A sweep skips its complete members "
                   "and resumes the interrupted one");
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
  const bool split = world_ && world_->distributed();
  if (!split) {
    write_checkpoint(dir_ / kCheckpointFileName, params_, c, outputs_);
  } else {
    // Rank 0 writes the whole grid; the gathers are collective, so every rank takes part.
    Checkpoint whole;
    whole.cursor = c.cursor;
    whole.step = c.step;
    whole.time = c.time;
    whole.last_step_converged = c.last_step_converged;
    whole.elapsed = c.elapsed;
    whole.stepper.nu_valid = c.stepper.nu_valid;
    whole.stepper.history_valid = c.stepper.history_valid;
    whole.stepper.prev_dt = c.stepper.prev_dt;
    Field phi = gathered(c.result.phi, 2);
    if (c.stepper.nu_valid) whole.stepper.nu = gathered(c.stepper.nu, 1);
    if (c.stepper.history_valid) {
      whole.stepper.prev_phi = gathered(c.stepper.prev_phi, 0);
      whole.stepper.prev_nu = gathered(c.stepper.prev_nu, 0);
    }
    if (world_->rank() == 0) {
      RunResult r = c.result;  // its block's copy is small; the whole phi replaces it
      r.phi = std::move(phi);
      whole.result = std::move(r);
      write_checkpoint(dir_ / kCheckpointFileName, params_, whole, outputs_);
    }
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
  CheckpointFile f;
  try {
    f = read_checkpoint(file);
  } catch (const CheckpointError& e) {
    throw UsageError(fmt::format("--resume: {}", e.what()));
  }
  // Before any field is cut into blocks: the run of these parameters must pass through the
  // checkpoint's grid and stage, on this many processes.
  const bool split = world && world->distributed();
  const std::string problem = resume_problem(f.checkpoint, params_from_json(f.params), entry,
                                             split ? world.get() : nullptr);
  if (!problem.empty())
    throw UsageError(fmt::format("--resume: {}: a run with its parameters cannot continue it{}: {}",
                                 file.string(),
                                 split ? fmt::format(" on {} processes", world->ranks()) : "",
                                 problem));
  LoadedCheckpoint loaded{std::move(f.params), std::move(f.outputs), nullptr};
  auto c = std::make_shared<Checkpoint>(std::move(f.checkpoint));
  if (split) {  // this process's blocks of the whole fields
    auto cut = [&](Field& whole) {
      if (whole.n() == 0) return;
      Field block(whole.n(), whole.ghost(), world);
      take_block(whole, block);
      block.exchange_halo();
      whole = std::move(block);
    };
    cut(c->result.phi);
    cut(c->stepper.nu);
    cut(c->stepper.prev_phi);
    cut(c->stepper.prev_nu);
  }
  loaded.checkpoint = std::move(c);
  return loaded;
}

void OutputRestorer::throw_bad(const char* key) const {
  throw UsageError(fmt::format("--resume: {}: output option '{}' is {}, not a value of its "
                               "type",
                               file_.string(), key, saved_.at(key).dump()));
}

void remove_leftover_temporaries(const fs::path& dir, bool quiet) {
  const int removed = remove_stale_temporaries(dir);
  if (removed > 0 && !quiet)
    std::cerr << fmt::format("removed {} unfinished temporary file(s) an earlier process left "
                             "in {}\n",
                             removed, dir.string());
}

RunParams resumed_params(const CLI::App& app, const RunParams& given, const nlohmann::json& saved,
                         const fs::path& file) {
  RunParams p;
  try {
    p = params_from_json(saved);
  } catch (const std::exception& e) {
    throw UsageError(fmt::format("--resume: {}: {}", file.string(), e.what()));
  }
  const nlohmann::json mine = params_json(given), theirs = params_json(p);
  for (const CLI::Option* o : app.get_options()) {
    if (o->count() == 0) continue;
    for (std::string key : o->get_lnames()) {
      std::replace(key.begin(), key.end(), '-', '_');
      if (!theirs.contains(key) || mine[key] == theirs[key]) continue;
      throw UsageError(fmt::format(
          "--{} {}: {} was written by a run with {} {}; a resumed run keeps the parameters it "
          "started with (leave the option out, or start a new run with another --out)",
          o->get_lnames().front(), mine[key].dump(), file.string(), key, theirs[key].dump()));
    }
  }
  return p;
}

}  // namespace cmcsurf::cli
