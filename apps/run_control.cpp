#include "run_control.h"

#include <unistd.h>

#include <csignal>
#include <cstring>
#include <iostream>

#include <fmt/format.h>

#include "cli_common.h"
#include "common/atomic_file.h"
#include "io/json_file.h"
#include "io/run_report.h"
#include "schema/report_schema.h"

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

CheckpointSink signal_checkpoint_sink(fs::path dir, const RunParams& params,
                                      nlohmann::json outputs, double every,
                                      std::shared_ptr<const Decomposition> world) {
  return CheckpointSink(
      std::move(dir), params, std::move(outputs), every, std::move(world),
      [] { return g_signal != 0; },
      [](const std::string& why) { std::cerr << fmt::format("\nwarning: {}\n", why); });
}

std::string self_executable() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? "cmcsurf" : exe.string();
}

std::string stop_signal_name() { return signal_name(SignalGuard::received()); }

int print_interrupted(const fs::path& dir, const Checkpoint& c, const InterruptedRun& left,
                      const std::string& resume_command, bool quiet) {
  if (!left.failure.empty()) {
    std::cerr << fmt::format("\nerror: interrupted at step {}, but no checkpoint was written: {}\n",
                             c.step, left.failure);
    return kExitFailure;
  }
  if (left.root && !quiet)
    std::cerr << fmt::format(
        "\ninterrupted by {} before step {} ({} on {}^3, {:.1f} s of work kept in {})\n"
        "resume with: {}\n",
        signal_name(SignalGuard::received()), c.step + 1, run_stage_name(c.cursor.stage),
        c.cursor.grid, c.elapsed, (dir / kCheckpointFileName).string(), resume_command);
  return SignalGuard::exit_code();
}

int finish_interrupted(const fs::path& dir, const RunParams& params, RunInterrupted& stop,
                       CheckpointSink& sink, int threads, const std::string& resume_command,
                       bool quiet, const nlohmann::json& extra) {
  const InterruptedRun left = write_interrupted_run(dir, params, stop, sink, threads,
                                                    resume_command, stop_signal_name(), extra);
  return print_interrupted(dir, stop.checkpoint, left, resume_command, quiet);
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
  // Every option add_run_options made, compared by its key (whatever its CLI name).
  auto cli = [&](const RunOption& o) -> const CLI::Option* {
    for (const auto& [entry, option] : options.options)
      if (entry == &o) return option;
    return nullptr;
  };
  return as_usage([&] {
    return resumed_run_params(
        given, saved, file,
        [&](const RunOption& e) { return cli(e) != nullptr && cli(e)->count() > 0; },
        [&](const RunOption& e) { return "--" + cli(e)->get_lnames().front(); });
  });
}

}  // namespace cmcsurf::cli
