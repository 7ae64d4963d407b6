// cmcsurf sweep: families of CMC surfaces over volume fraction (Section 4.5, Fig. 11).
#include <fmt/format.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "cli_common.h"
#include "commands.h"
#include "io/atomic_file.h"
#include "io/build_info.h"
#include "io/json_file.h"
#include "io/png.h"
#include "io/run_report.h"
#include "io/vti.h"
#include "pipeline/option_checks.h"
#include "pipeline/preview.h"
#include "pipeline/run_outputs.h"
#include "pipeline/sweep.h"
#include "page_options.h"
#include "pipeline/run_page.h"
#include "run_control.h"

namespace cmcsurf::cli {

namespace {

namespace fs = std::filesystem;

struct SweepCommand {
  RunParams params;
  RunOptionStrings strings;
  std::string surfaces = "P,D,G";
  std::string fractions = "0.25:0.75:0.05";
  bool continuation = false;
  int threads = 0;
  std::string out = "cmcsurf-sweep";
  bool quiet = false;
  bool float32 = false;
  bool no_plot = false;
  std::string python = "/usr/bin/python3";
  std::string plot_script;
  PageOptions pages;  // --no-preview, --no-report
  CheckpointOptions checkpoints;  // --checkpoint-every, --resume
};

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// scripts/plot_families.py: --plot-script, $CMCSURF_PLOT_SCRIPT, beside the executable
// (../scripts, ../share/cmcsurf), or in the source tree this file was compiled from.
fs::path find_plot_script(const std::string& given) {
  if (!given.empty()) return given;
  if (const char* env = std::getenv("CMCSURF_PLOT_SCRIPT")) return env;
  std::vector<fs::path> candidates;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    candidates.push_back(exe.parent_path().parent_path() / "scripts" / "plot_families.py");
    candidates.push_back(exe.parent_path().parent_path() / "share" / "cmcsurf" / "plot_families.py");
  }
  candidates.push_back(fs::path(__FILE__).parent_path().parent_path() / "scripts" /
                       "plot_families.py");
  for (const fs::path& p : candidates)
    if (fs::exists(p, ec)) return p;
  return {};
}

// Runs the plotting script; a missing Python, script or matplotlib is a warning, not a failure.
void plot(const SweepCommand& cmd, const fs::path& dir) {
  const fs::path script = find_plot_script(cmd.plot_script);
  if (script.empty()) {
    std::cerr << "warning: scripts/plot_families.py not found (pass --plot-script); no figures\n";
    return;
  }
  const std::string command =
      fmt::format("{} {} {} {}", shell_quote(cmd.python), shell_quote(script.string()),
                  shell_quote((dir / "sweep.csv").string()), shell_quote((dir / "families").string()));
  const int status = std::system(command.c_str());
  const int rc = status == -1 ? -1 : (WIFEXITED(status) ? WEXITSTATUS(status) : -1);
  if (rc == 3)
    std::cerr << fmt::format(
        "warning: matplotlib is missing for {} (apt-get install python3-matplotlib); wrote "
        "sweep.csv without figures\n",
        cmd.python);
  else if (rc != 0)
    std::cerr << fmt::format("warning: '{}' failed (exit {}); wrote sweep.csv without figures\n",
                             command, rc);
}

SweepParams validate(SweepCommand& cmd) {
  SweepParams sp;
  finish_run_options(cmd.params, cmd.strings, false);
  try {
    sp.surfaces = parse_surface_list(cmd.surfaces);
  } catch (const std::invalid_argument& e) {
    throw UsageError(fmt::format("--surface: {}", e.what()));
  }
  try {
    sp.fractions = parse_volume_fractions(cmd.fractions);
  } catch (const std::invalid_argument& e) {
    throw UsageError(fmt::format("--volume-fractions: {}", e.what()));
  }
  if (fs::exists(cmd.out) && !fs::is_directory(cmd.out))
    throw UsageError(fmt::format("--out: '{}' exists and is not a directory", cmd.out));
  sp.run = cmd.params;
  sp.continuation = cmd.continuation;
  return sp;
}

void print_member(const SweepMember& m, const RunResult& r, const CmcQuality& quality) {
  std::cerr << fmt::format(
      "[{}/{}] {}: {} steps, {:.1f} s: area {:.5f} H {:+.4f} (local std {:.3g}, nodal {:.3g}) "
      "nodal area excess {:+.3f}%{}\n",
      m.index + 1, m.count, m.name, r.steps, r.wall_seconds, r.final.area, r.final.mean_curvature,
      quality.relaxed.std, quality.nodal.std,
      quality.has_nodal ? 100.0 * (quality.nodal_area / r.final.area - 1.0) : 0.0,
      r.converged ? "" : " NOT converged");
}

// What the sweep writes besides the members' fields, kept in sweep.json (and each member's
// checkpoint): `sweep --resume DIR` alone writes the folder the uninterrupted sweep would have.
nlohmann::json output_options(const SweepCommand& cmd) {
  return {{"threads", cmd.threads},
          {"float32", cmd.float32},
          {"no_preview", cmd.pages.no_preview},
          {"no_report", cmd.pages.no_report},
          {"no_plot", cmd.no_plot},
          {"python", cmd.python},
          {"plot_script", cmd.plot_script},
          {"checkpoint_every", cmd.checkpoints.every}};
}

// sweep.json: what the sweep was (per-member parameters are in each report.json).
nlohmann::json sweep_summary(const SweepParams& sp, const SweepCommand& cmd, std::size_t members,
                             int threads, double wall) {
  nlohmann::json summary = {{"members", members},
                            {"surfaces", sp.surfaces},
                            {"volume_fractions", sp.fractions},
                            {"continuation", sp.continuation},
                            {"threads", threads},
                            {"wall_seconds", wall},
                            {"version", version_string()},
                            {"build", build_info_json()},
                            {"parameters", params_json(sp.run)},
                            {"outputs", output_options(cmd)}};
  summary["parameters"].erase("surface");  // per member
  summary["parameters"].erase("volume_fraction");
  return summary;
}

// sweep --resume: the sweep that sweep.json describes (its ranges checked as the command
// line's); options given must agree with it, output options not given take its values.
SweepParams resumed_sweep(const CLI::App& app, const SweepParams& given, SweepCommand& cmd,
                          const fs::path& dir) {
  const fs::path file = dir / "sweep.json";
  SweepParams sp;
  nlohmann::json j;
  try {
    j = read_json_file(file);
    j.at("surfaces").get_to(sp.surfaces);
    j.at("volume_fractions").get_to(sp.fractions);
    j.at("continuation").get_to(sp.continuation);
    sp.run = resumed_params(app, given.run, j.at("parameters"), file);
  } catch (const UsageError&) {
    throw;
  } catch (const std::exception& e) {
    throw UsageError(fmt::format("--resume {}: no sweep to resume ({})", dir.string(), e.what()));
  }
  try {
    check_sweep_params(sp);
  } catch (const std::invalid_argument& e) {
    throw UsageError(fmt::format("--resume: {}: {}", file.string(), e.what()));
  }
  if (j.contains("outputs")) {
    if (!j["outputs"].is_object())
      throw UsageError(fmt::format("--resume: {}: 'outputs' is not an object", file.string()));
    const OutputRestorer r(app, j["outputs"], file);
    r.restore("--threads", "threads", cmd.threads);
    if (const std::string why = check_threads(cmd.threads); !why.empty())
      throw UsageError(fmt::format("--resume: {}: threads: {}", file.string(), why));
    r.restore("--float32", "float32", cmd.float32);
    r.restore("--no-preview", "no_preview", cmd.pages.no_preview);
    r.restore("--no-report", "no_report", cmd.pages.no_report);
    r.restore("--no-plot", "no_plot", cmd.no_plot);
    r.restore("--python", "python", cmd.python);
    r.restore("--plot-script", "plot_script", cmd.plot_script);
    r.restore("--checkpoint-every", "checkpoint_every", cmd.checkpoints.every);
    if (!(cmd.checkpoints.every >= 0.0 && cmd.checkpoints.every <= 1e9))
      throw UsageError(fmt::format("--resume: {}: checkpoint_every {} outside [0, 1e9]",
                                   file.string(), cmd.checkpoints.every));
  }
  auto differs = [&](const char* option, bool d) {
    if (d && app.count(option))
      throw UsageError(fmt::format("{}: differs from the sweep in {} ({}); a resumed sweep keeps "
                                   "its members (leave the option out)",
                                   option, file.string(), option));
  };
  differs("--surface", given.surfaces != sp.surfaces);
  differs("--volume-fractions", given.fractions != sp.fractions);
  differs("--continuation", given.continuation != sp.continuation);
  return sp;
}

// Stops a sweep between two members when a signal arrived while one was being written.
struct StopBetweenMembers {};

int sweep(SweepCommand& cmd, const CLI::App& app) {
  const bool resuming = !cmd.checkpoints.resume.empty();
  if (resuming) {
    if (app.count("--out") && fs::path(cmd.out) != cmd.checkpoints.resume)
      throw UsageError(fmt::format("--out {}: a resumed sweep writes into its own folder, "
                                   "--resume {}",
                                   cmd.out, cmd.checkpoints.resume));
    cmd.out = cmd.checkpoints.resume;
  }
  SweepParams sp = validate(cmd);
  const fs::path dir(cmd.out);
  if (resuming) sp = resumed_sweep(app, sp, cmd, dir);
  const int threads = apply_threads(cmd.threads);
  cmd.threads = threads;  // the count in use, kept in sweep.json for a resume
  const auto t0 = std::chrono::steady_clock::now();
  ensure_directory(dir);
  remove_leftover_temporaries(dir, cmd.quiet);  // of an earlier process killed mid-write
  // sweep.json first, marked incomplete, so that an interrupted sweep can be resumed.
  if (!resuming) {
    nlohmann::json started =
        sweep_summary(sp, cmd, sp.surfaces.size() * sp.fractions.size(), threads, 0);
    started["complete"] = false;
    write_json_atomic(dir / "sweep.json", started);
  }
  const std::string resume_cmd = fmt::format("{} sweep --resume {}", self_executable(), dir.string());
  SignalGuard signals;
  CheckpointSink sink(dir, sp.run, output_options(cmd), cmd.checkpoints.every, nullptr);
  SweepMember current;
  int skipped = 0, resumed = 0;
  std::vector<nlohmann::json> reports;
  std::vector<GalleryMember> gallery;
  Progress progress(cmd.quiet);
  auto starting = [&](const SweepMember& m) {
    if (!cmd.quiet)
      std::cerr << fmt::format("[{}/{}] {} alpha {} from {}\n", m.index + 1, m.count, m.surface,
                               m.alpha, m.started_from);
  };
  auto done = [&](const SweepMember& m, RunResult& r) {
    // Quality, preview.png and report.html's meshes (docs/report.md).
    RunOutputs outputs =
        run_outputs(r.phi, m.params, r, !cmd.pages.no_preview, !cmd.pages.no_report);
    const CmcQuality& quality = outputs.quality;
    std::optional<RunPreview>& preview = outputs.preview;
    nlohmann::json extra = {{"volume_fraction_target", m.alpha},  // also if continued
                            {"member", m.name},
                            {"started_from", m.started_from}};
    if (preview) extra["preview_seconds"] = preview->seconds;
    if (outputs.page) extra["page_seconds"] = outputs.page_seconds;
    reports.push_back(write_run_folder(dir / m.name, m.params, r, r.phi, quality, threads,
                                       cmd.float32, extra, [&] {
                                         if (preview)
                                           write_png(dir / m.name / "preview.png", preview->image);
                                       }));
    fs::remove(dir / m.name / kCheckpointFileName);  // the member is complete
    if (outputs.page) write_run_page(dir / m.name, &*outputs.page);
    if (preview)
      gallery.push_back({m.surface, m.name, m.alpha, r.final.mean_curvature,
                         std::move(preview->surfaces.relaxed)});
    write_file_atomic(dir / "sweep.csv", sweep_csv(reports));  // after every member
    progress.finish();
    if (!cmd.quiet) print_member(m, r, quality);
  };
  // Each member's folder: kept when complete (resume), continued from its checkpoint, or
  // cleared of an earlier run's outputs.
  auto plan = [&](const SweepMember& m) {
    if (SignalGuard::received()) throw StopBetweenMembers{};
    current = m;
    const fs::path mdir = dir / m.name;
    sink.retarget(mdir, m.params);
    if (fs::is_directory(mdir)) remove_leftover_temporaries(mdir, cmd.quiet);
    MemberStart start;
    if (resuming && fs::exists(mdir / kCheckpointFileName)) {
      // A continued member goes on through relax_to_volume_fraction, the first of a family
      // through run_cmc (pipeline/sweep.h): the checkpoint must fit that run.
      const RunEntry entry =
          m.started_from == "nodal" ? RunEntry::kCmc : RunEntry::kRelaxToVolume;
      LoadedCheckpoint loaded = load_checkpoint(mdir, entry, nullptr);
      start.checkpoint = std::move(loaded.checkpoint);
      if (loaded.params != params_json(m.params))
        throw UsageError(fmt::format("--resume: {} belongs to a run with other parameters than "
                                     "the sweep's member {}",
                                     (mdir / kCheckpointFileName).string(), m.name));
      start.kind = MemberStart::Kind::kResume;
      ++resumed;
      if (!cmd.quiet)
        std::cerr << fmt::format("[{}/{}] {}: resuming before step {} ({} on {}^3)\n",
                                 m.index + 1, m.count, m.name, start.checkpoint->step + 1,
                                 start.checkpoint->cursor.stage, start.checkpoint->cursor.grid);
      return start;
    }
    if (resuming && fs::exists(mdir / "report.json")) {
      nlohmann::json report = read_json_file(mdir / "report.json");
      if (report.value("stop_reason", "") != "interrupted" && fs::exists(mdir / "field.vti") &&
          report.value("parameters", nlohmann::json()) == params_json(m.params) &&
          report.value("started_from", "") == m.started_from) {
        start.kind = MemberStart::Kind::kSkip;
        if (sp.continuation)
          start.field =
              std::move(read_vti(mdir / "field.vti", VtiReadOptions{2, 1 << 13, "phi"}).arrays["phi"]);
        reports.push_back(std::move(report));
        write_file_atomic(dir / "sweep.csv", sweep_csv(reports));
        // Its tile, so that gallery.png shows every member (as the uninterrupted sweep's).
        if (!cmd.pages.no_preview)
          gallery.push_back(gallery_member_from_folder(mdir, m.surface, m.name, m.alpha));
        ++skipped;
        if (!cmd.quiet)
          std::cerr << fmt::format("[{}/{}] {}: complete, kept\n", m.index + 1, m.count, m.name);
        return start;
      }
    }
    ensure_directory(mdir);
    clear_run_outputs(mdir);
    fs::remove(mdir / kCheckpointFileName);
    return start;
  };
  RunContext context([&](const StepRecord& s) { progress.step(s); });
  sink.attach(context);
  try {
    run_sweep(sp, starting, done, context, plan);
  } catch (RunInterrupted& stop) {
    progress.finish();
    return finish_interrupted(dir / current.name, current.params, stop, sink, threads,
                              resume_cmd, cmd.quiet,
                              {{"volume_fraction_target", current.alpha},
                               {"member", current.name},
                               {"started_from", current.started_from}});
  } catch (const StopBetweenMembers&) {
    std::cerr << fmt::format("\ninterrupted by a signal between members ({} complete)\n"
                             "resume with: {}\n",
                             reports.size(), resume_cmd);
    return SignalGuard::exit_code();
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!cmd.no_plot) plot(cmd, dir);
  nlohmann::json summary = sweep_summary(sp, cmd, reports.size(), threads, wall);
  summary["complete"] = true;
  if (resuming) summary["resumed"] = {{"members_kept", skipped}, {"members_resumed", resumed}};
  if (!gallery.empty()) summary["gallery_seconds"] = write_gallery(dir, gallery);
  write_json_atomic(dir / "sweep.json", summary);
  if (!cmd.pages.no_report) write_sweep_page(dir);
  if (!cmd.quiet)
    std::cerr << fmt::format("sweep: {} members in {:.1f} s; wrote {}/sweep.csv{}\n",
                             reports.size(), wall, dir.string(),
                             fs::exists(dir / "families.png") ? ", families.png/.svg" : "");
  return 0;
}

}  // namespace

CommandFn add_sweep_command(CLI::App& root) {
  auto cmd = std::make_shared<SweepCommand>();
  CLI::App* app = root.add_subcommand(
      "sweep",
      "Families of CMC surfaces over volume fraction (Fig. 11): sweep.csv, one folder per "
      "member, figures families.png/.svg");
  app->add_option("--surface", cmd->surfaces,
                  "Comma-separated nodal surfaces (P, D, G, ... or expr:<formula>)")
      ->capture_default_str();
  app->add_option("--volume-fractions", cmd->fractions,
                  "start:stop:step (stop included) or a list a,b,c; each in (0, 1)")
      ->capture_default_str();
  add_run_options(*app, cmd->params, cmd->strings, false);
  app->add_flag("--continuation", cmd->continuation,
                "Start each member from the previous member's field shifted to the new mean, "
                "instead of the nodal formula");
  add_threads_option(*app, cmd->threads);
  app->add_option("--out", cmd->out, "Output directory")->capture_default_str();
  app->add_flag("--float32", cmd->float32, "Write field.vti in single precision");
  app->add_flag("--no-plot", cmd->no_plot, "Skip the figures");
  app->add_option("--python", cmd->python, "Python with matplotlib for the figures")
      ->capture_default_str();
  app->add_option("--plot-script", cmd->plot_script, "Path of scripts/plot_families.py");
  app->add_flag("--quiet", cmd->quiet, "No progress output");
  add_page_options(*app, cmd->pages);
  add_checkpoint_options(*app, cmd->checkpoints, true);
  return {app, [cmd, app]() -> int { return sweep(*cmd, *app); }};
}

}  // namespace cmcsurf::cli
