// cmcsurf sweep: families of CMC surfaces over volume fraction (Section 4.5, Fig. 11).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "common/wall_clock.h"
#include "cahn_hilliard/time_step.h"
#include "cli_common.h"
#include "commands.h"
#include "common/atomic_file.h"
#include "io/build_info.h"
#include "io/json_file.h"
#include "io/png.h"
#include "io/run_report.h"
#include "io/pvti.h"
#include "io/run_folder.h"
#include "io/vti.h"
#include "parallel/decomposition.h"
#include "model/option_checks.h"
#include "pipeline/preview.h"
#include "pipeline/properties_pictures.h"
#include "pipeline/properties_stage.h"
#include "pipeline/run_outputs.h"
#include "pipeline/sweep.h"
#include "driver/sweep_driver.h"
#include "pipeline/sweep_groups.h"
#include "page_options.h"
#include "properties_options.h"
#include "report/run_page.h"
#include "run_control.h"
#include "schema/report_schema.h"

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
  int groups = 0;  // --groups: 0 picks (GroupPlan)
  std::string out = "cmcsurf-sweep";
  bool quiet = false;
  bool float32 = false;
  bool no_plot = false;
  bool plot_diffuse = false;  // --plot-diffuse: families.png shows the diffuse layer's values
  std::string python;         // --python, --plot-script: accepted, no longer used
  std::string plot_script;
  PageOptions pages;  // --no-preview, --no-report
  CheckpointOptions checkpoints;  // --checkpoint-every, --resume
  bool force = false;             // --force: a non-empty folder cmcsurf did not write
  PropertiesOptions properties;   // --properties, --properties-*: each member's solid
};

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
  try {
    check_sweep_params(sp);  // members with one name (G,G or 0.5,0.5)
  } catch (const std::invalid_argument& e) {
    throw UsageError(fmt::format("--surface, --volume-fractions: {}", e.what()));
  }
  return sp;
}

double number_in(const nlohmann::json& report, const char* key) {
  const auto it = report.find(key);
  return it != report.end() && it->is_number() ? it->get<double>() : NAN;
}

// A member's line from its report.json, in the formats of the report key table
// (schema/report_schema.h, member_line); `where`: " (group G)" for another group's member.
void print_member_line(const nlohmann::json& r, int index, int count, const std::string& where) {
  auto number = [&](const char* key) { return member_line_number(key, number_in(r, key)); };
  const double excess = number_in(r, "nodal_area_excess");
  std::cerr << fmt::format(
      "[{}/{}] {}{}: {} steps, {} s: area {} H {} (local std {}, nodal {}) nodal area excess "
      "{}{}\n",
      index + 1, count, r.value("member", "?"), where, number("steps"), number("wall_seconds"),
      number("area"), number("mean_curvature"), number("mean_curvature_std"),
      number("nodal_mean_curvature_std"),
      member_line_number("nodal_area_excess", std::isfinite(excess) ? excess : 0.0),
      r.value("converged", false) ? "" : " NOT converged");
}

// sweep --resume: the sweep that sweep.json describes (pipeline/run_resume.h: its ranges
// checked as the command line's, the options given agreeing with it); output options not
// given take its values.
SweepParams resumed_sweep(const CLI::App& app, const SweepParams& given, SweepCommand& cmd,
                          const fs::path& dir) {
  const fs::path file = dir / "sweep.json";
  SweepResumeNames names;
  names.surfaces_given = app.count("--surface") > 0;
  names.fractions_given = app.count("--volume-fractions") > 0;
  names.continuation_given = app.count("--continuation") > 0;
  const SweepJson saved = as_usage([&] {
    return cmcsurf::resumed_sweep(
        dir, given, names, [&](const nlohmann::json& parameters, const fs::path& from) {
          return resumed_params(cmd.strings, given.run, parameters, from);
        });
  });
  const OutputRestorer r(app, saved.outputs, file);
  r.restore("--threads", "threads", cmd.threads);
  if (const std::string why = check_threads(cmd.threads); !why.empty())
    throw UsageError(fmt::format("--resume: {}: threads: {}", file.string(), why));
  r.restore("--float32", "float32", cmd.float32);
  r.restore("--no-preview", "no_preview", cmd.pages.no_preview);
  r.restore("--no-report", "no_report", cmd.pages.no_report);
  r.restore("--no-plot", "no_plot", cmd.no_plot);
  r.restore("--plot-diffuse", "plot_diffuse", cmd.plot_diffuse);
  restore_properties_outputs(r, cmd.properties);
  r.restore("--checkpoint-every", "checkpoint_every", cmd.checkpoints.every);
  if (!(cmd.checkpoints.every >= 0.0 && cmd.checkpoints.every <= 1e9))
    throw UsageError(fmt::format("--resume: {}: checkpoint_every {} outside [0, 1e9]",
                                 file.string(), cmd.checkpoints.every));
  return saved.sweep;
}

// The sweep driver (driver/sweep_driver.h) with the command line's options and printing.
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
  const auto world = Decomposition::world();
  SweepJob job;
  job.plan = as_usage([&] { return plan_groups(cmd.groups, sp, *world); });
  refuse_if_too_large(sp.run, *world, job.plan.group_ranks);  // before the folder is touched
  finish_properties_options(cmd.properties, sp.surfaces.front(), sp.run.grid);
  if (cmd.properties.stage.enabled && job.plan.group_ranks > 1)
    throw UsageError(fmt::format(
        "--properties: the properties solvers hold a member's whole grid; with groups of {} "
        "processes they cannot run (use --groups {} for groups of one process, or `cmcsurf "
        "properties` on the members afterwards)",
        job.plan.group_ranks, world->ranks()));
  const int threads = apply_threads(cmd.threads);
  cmd.threads = threads;  // the count in use, kept in sweep.json for a resume
  const bool world_root = world->rank() == 0;
  // One writer, and only into a folder that is ours (or new, or empty), before any work.
  const FolderClaim claim = claim_folder(
      dir, {.kind = "sweep", .option = resuming ? "--resume" : "--out", .force = cmd.force},
      *world);
  job.sweep = sp;
  job.dir = dir;
  job.resuming = resuming;
  job.force = cmd.force;
  job.member.threads = threads;
  job.member.float32 = cmd.float32;
  job.member.properties = cmd.properties.stage;
  job.preview = !cmd.pages.no_preview;
  job.page = !cmd.pages.no_report;
  job.figures = !cmd.no_plot;
  job.diffuse = cmd.plot_diffuse;
  job.checkpoint_every = cmd.checkpoints.every;
  job.outputs = sweep_outputs_json(job, cmd.properties.porosity);
  job.resume_command = fmt::format("{} sweep --resume {}", shell_quote(self_executable()),
                                   shell_quote(dir.string()));
  if (world->distributed())
    job.resume_command = fmt::format("mpirun -np {} {}", world->ranks(), job.resume_command);
  SignalGuard signals;
  Progress progress(cmd.quiet || !world_root);
  auto print = [](const std::string& text) { std::cerr << text; };
  auto print_unless_quiet = [&](const std::string& text) {
    if (!cmd.quiet) std::cerr << text;
  };
  SweepHooks hooks;
  hooks.note = print_unless_quiet;
  hooks.notice = print;
  hooks.error = print;
  hooks.starting = [&](const SweepMember& m) {
    if (!cmd.quiet)
      std::cerr << fmt::format("[{}/{}] {} alpha {} from {}\n", m.index + 1, m.count, m.surface,
                               m.alpha, m.started_from);
  };
  hooks.resuming = [&](const SweepMember& m, const Checkpoint& c) {
    if (!cmd.quiet)
      std::cerr << fmt::format("[{}/{}] {}: resuming before step {} ({} on {}^3)\n",
                               m.index + 1, m.count, m.name, c.step + 1,
                               run_stage_name(c.cursor.stage), c.cursor.grid);
  };
  hooks.kept = [&](const SweepMember& m, const nlohmann::json&) {
    if (!cmd.quiet)
      std::cerr << fmt::format("[{}/{}] {}: complete, kept\n", m.index + 1, m.count, m.name);
  };
  hooks.finished = [&](const SweepMember& m, const nlohmann::json& report) {
    if (!cmd.quiet) print_member_line(report, m.index, m.count, "");
  };
  hooks.gathered = [&](const nlohmann::json& report, int index, int count, int group) {
    if (!cmd.quiet) print_member_line(report, index, count, fmt::format(" (group {})", group));
  };
  hooks.step = [&](const StepRecord& s) { progress.step(s); };
  hooks.steps_done = [&] { progress.finish(); };
  hooks.stop_requested = [] { return SignalGuard::received() != 0; };
  hooks.stop_code = [] { return SignalGuard::exit_code(); };
  hooks.signal_name = [] { return stop_signal_name(); };
  hooks.interrupted = [&](const fs::path& mdir, const Checkpoint& c, const InterruptedRun& left) {
    print_interrupted(mdir, c, left, job.resume_command, cmd.quiet);
  };
  hooks.warning = [](const std::string& why) {
    std::cerr << fmt::format("\nwarning: {}\n", why);
  };
  const SweepOutcome outcome = drive_sweep(job, hooks);
  if (outcome.exit_code == 0 && world_root && !cmd.quiet)
    std::cerr << fmt::format("sweep: {} members in {:.1f} s; wrote {}/sweep.csv{}\n",
                             outcome.members, outcome.wall_seconds, dir.string(),
                             outcome.families_figure ? ", families.png/.svg" : "");
  return outcome.exit_code;
}

}  // namespace

CommandFn add_sweep_command(CLI::App& root) {
  auto cmd = std::make_shared<SweepCommand>();
  CLI::App* app = root.add_subcommand(
      "sweep",
      "Families of CMC surfaces over volume fraction (Fig. 11): sweep.csv, one folder per "
      "member, figures families.png/.svg. Under mpirun the members run side by side in groups "
      "of ranks (--groups)");
  app->add_option("--surface", cmd->surfaces,
                  "Comma-separated nodal surfaces (P, D, G, ... or expr:<formula>)")
      ->capture_default_str();
  app->add_option("--volume-fractions", cmd->fractions,
                  "start:stop:step (stop included) or a list a,b,c; each in (0, 1)")
      ->capture_default_str();
  add_run_options(*app, cmd->params, cmd->strings, false);
  add_run_option(*app, cmd->params, cmd->strings, "structure");  // each member's seed
  app->add_flag("--continuation", cmd->continuation,
                "Start each member from the previous member's field shifted to the new mean, "
                "instead of the nodal formula");
  add_threads_option(*app, cmd->threads);
  app->add_option("--groups", cmd->groups,
                  "Under mpirun: run the members side by side in G groups of equal size, each "
                  "member decomposed over its group's processes (G divides the rank count; with "
                  "--continuation a group runs whole families). 0: as many groups as members "
                  "(families) up to the rank count, in as few rounds, with blocks that split "
                  "the grid")
      ->capture_default_str();
  app->add_option("--out", cmd->out, "Output directory")
      ->capture_default_str()
      ->check(non_empty_text(), "DIR");
  app->add_flag("--float32", cmd->float32,
                "Write each member's field (field.vti, or field.pvti under a group of several "
                "processes) in single precision");
  app->add_flag("--no-plot", cmd->no_plot, "Skip the figures");
  app->add_flag("--plot-diffuse", cmd->plot_diffuse,
                "families.png: also the diffuse layer's H and area (Appendix B), dotted, beside "
                "the sharp values with their error bars");
  app->add_option("--python", cmd->python,
                  "No longer used: cmcsurf draws families.png itself (accepted for old scripts)");
  app->add_option("--plot-script", cmd->plot_script,
                  "No longer used: cmcsurf draws families.png itself (accepted for old scripts)");
  add_force_option(*app, cmd->force);
  add_properties_options(*app, cmd->properties, "each member's");
  app->add_flag("--quiet", cmd->quiet, "No progress output");
  add_page_options(*app, cmd->pages);
  add_checkpoint_options(*app, cmd->checkpoints, true);
  return {app, [cmd, app]() -> int { return sweep(*cmd, *app); }};
}

}  // namespace cmcsurf::cli
