#include "cli_common.h"

#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <type_traits>
#include <variant>
#include <fmt/format.h>

#include "common/atomic_file.h"
#include "io/json_file.h"
#include "io/run_report.h"
#include "io/vti.h"
#include "multigrid/fas.h"
#include "parallel/decomposition.h"
#include "parallel/threads.h"
#include "model/option_checks.h"
#include "pipeline/sweep.h"
#include "surfaces/initial.h"

namespace cmcsurf::cli {

std::string version_string() { return CMCSURF_VERSION; }

std::string plus_minus(double error) {
  return std::isfinite(error) ? fmt::format(" +- {:.1e}", error) : std::string();
}

namespace {

// An integer option's text through the library's check (model/option_checks.h), so that
// Python says the same; text that is no integer is left to CLI11 ("Could not convert").
std::function<std::string(const std::string&)> library_check(std::string (*check)(long long)) {
  return [check](const std::string& text) -> std::string {
    errno = 0;
    char* end = nullptr;
    const long long v = std::strtoll(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0') return {};
    if (errno == ERANGE) {  // beyond long long; only a seed may still fit (unsigned 64 bits)
      errno = 0;
      std::strtoull(text.c_str(), nullptr, 10);
      if (errno == ERANGE || text.find('-') != std::string::npos)
        return fmt::format("got {}: beyond a 64-bit integer", text);
    }
    return check(v);  // clamped to long long: refused by the range check where it matters
  };
}

}  // namespace

namespace {

// One entry of the run option table as a CLI11 option (under `solver` if it is of that group).
void add_entry(CLI::App& app, CLI::App*& solver, const RunOption& o, RunParams& p,
               RunOptionStrings& s) {
  if (o.solver_group && solver == nullptr)
    solver = app.add_option_group("solver", "Multigrid and algorithm details");
  CLI::App& to = o.solver_group ? *solver : app;
  CLI::Option* added = std::visit(
      [&](const auto& ref) -> CLI::Option* {
        using R = std::decay_t<decltype(ref)>;
        if constexpr (std::is_same_v<R, RunChoice>) {
          std::string& text = s.choices.text[o.key];
          text = ref.names.at(ref.get(p));
          return to.add_option(o.cli, text, o.help)->capture_default_str();
        } else if constexpr (std::is_same_v<R, RunMember<bool>>) {
          return to.add_flag(o.cli, ref(p), o.help);
        } else {
          CLI::Option* opt = to.add_option(o.cli, ref(p), o.help);
          if (o.integer_check != nullptr) opt->check(library_check(o.integer_check));
          return opt->capture_default_str();
        }
      },
      o.ref);
  s.options.emplace_back(&o, added);
}

}  // namespace

void add_run_options(CLI::App& app, RunParams& p, RunOptionStrings& s, bool with_surface) {
  CLI::App* solver = nullptr;  // the "solver" heading, made where its first option comes
  for (const RunOption& o : run_option_table()) {
    if (*o.cli == '\0' || (o.scope == RunOptionScope::kSurface && !with_surface)) continue;
    add_entry(app, solver, o, p, s);
  }
}

void add_run_option(CLI::App& app, RunParams& p, RunOptionStrings& s, const std::string& key) {
  const RunOption* o = find_run_option(key);
  if (o == nullptr || *o->cli == '\0' || o->solver_group)
    throw std::logic_error("add_run_option: no command-line option " + key);
  CLI::App* solver = nullptr;
  add_entry(app, solver, *o, p, s);
}

void finish_run_options(RunParams& p, const RunOptionStrings& s, bool check_surface) {
  RunChoices c = s.choices;
  for (const auto& [o, cli] : s.options)
    if (cli->count() > 0) c.given.insert(o->key);
  try {
    finish_run_params(p, c, check_surface);
  } catch (const OptionError& e) {
    throw UsageError(e.what());
  }
}

void add_threads_option(CLI::App& app, int& threads) {
  app.add_option("--threads", threads,
                 "OpenMP threads per process (0: OMP_NUM_THREADS, else all cores or, under "
                 "mpirun, this rank's share of the cores it is bound to)")
      ->check(library_check(check_threads), "0 <= T <= " + std::to_string(kMaxThreads))
      ->capture_default_str();
}

int apply_threads(int threads) {
  const ThreadChoice choice = choose_threads(threads);  // parallel/threads.h
  if (!choice.warning.empty() && Decomposition::world()->rank() == 0)
    fmt::print(stderr, "warning: {}\n", choice.warning);
  return choice.threads;
}

Progress::Progress(bool quiet) : quiet_(quiet), tty_(isatty(fileno(stderr)) != 0) {}

void Progress::step(const StepRecord& r) {
  if (quiet_) return;
  last_ = r;
  last_printed_ = false;
  const bool new_stage = stage_text(r) != last_stage_;
  const double interval = tty_ ? 0.1 : 5.0;
  if (!new_stage && r.elapsed - last_print_ < interval) return;
  print(r, new_stage);
}

void Progress::print(const StepRecord& r, bool new_stage) {
  last_print_ = r.elapsed;
  last_stage_ = stage_text(r);
  last_printed_ = true;
  // The equilibrium stop rule's residual where it runs (the finest grid of the fast mode).
  const std::string equilibrium =
      std::isfinite(r.equilibrium_residual) ? fmt::format("  eq {:.2e}", r.equilibrium_residual)
                                            : std::string();
  const std::string line = fmt::format(
      "{:<8} step {:>6}  t {:9.4f}  area {:.8f}  dA {:+.3e}  V-cycles {:>2}{}  {:7.1f} s",
      stage_text(r), r.step, r.time, r.area, r.d_area, r.vcycles, equilibrium, r.elapsed);
  if (tty_) {
    if (new_stage && pending_newline_) std::fputc('\n', stderr);
    std::fprintf(stderr, "\r%s", line.c_str());
    pending_newline_ = true;
  } else {
    std::fprintf(stderr, "%s\n", line.c_str());
  }
  std::fflush(stderr);
}

void Progress::finish() {
  if (!quiet_ && !last_printed_) print(last_, stage_text(last_) != last_stage_);
  if (pending_newline_) std::fputc('\n', stderr);
  pending_newline_ = false;
}

}  // namespace cmcsurf::cli
