// cmcsurf sweep: families of CMC surfaces over volume fraction (Section 4.5, Fig. 11).
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <sys/wait.h>

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
#include "pipeline/sweep_groups.h"
#include "page_options.h"
#include "properties_options.h"
#include "report/run_page.h"
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
  int groups = 0;  // --groups: 0 picks (GroupPlan)
  std::string out = "cmcsurf-sweep";
  bool quiet = false;
  bool float32 = false;
  bool no_plot = false;
  std::string python = "/usr/bin/python3";
  std::string plot_script;
  PageOptions pages;  // --no-preview, --no-report
  CheckpointOptions checkpoints;  // --checkpoint-every, --resume
  bool force = false;             // --force: a non-empty folder cmcsurf did not write
  PropertiesOptions properties;   // --properties, --properties-*: each member's solid
};

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
    candidates.push_back(exe.parent_path().parent_path() / "share" / "cmcsurf" /
                         "plot_families.py");
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
  const std::string command = fmt::format(
      "{} {} {} {}", shell_quote(cmd.python), shell_quote(script.string()),
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
  try {
    check_sweep_params(sp);  // members with one name (G,G or 0.5,0.5)
  } catch (const std::invalid_argument& e) {
    throw UsageError(fmt::format("--surface, --volume-fractions: {}", e.what()));
  }
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
// Never which program draws the figures (--python, --plot-script): a data file that someone
// else may have written restores options, it never chooses an executable.
nlohmann::json output_options(const SweepCommand& cmd) {
  nlohmann::json outputs = {{"threads", cmd.threads},
                             {"float32", cmd.float32},
                             {"no_preview", cmd.pages.no_preview},
                             {"no_report", cmd.pages.no_report},
                             {"no_plot", cmd.no_plot},
                             {"checkpoint_every", cmd.checkpoints.every}};
  add_properties_outputs(outputs, cmd.properties);
  return outputs;
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
  SweepJson saved;  // checked: ranges, member names; no executables among its outputs
  try {
    j = read_json_file(file);
    saved = parse_sweep_json(j);
    sp = saved.sweep;
    sp.run = resumed_params(cmd.strings, given.run, j.at("parameters"), file);
  } catch (const UsageError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    throw UsageError(fmt::format("--resume: {}: {}", file.string(), e.what()));
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
    const OutputRestorer r(app, saved.outputs, file);
    r.restore("--threads", "threads", cmd.threads);
    if (const std::string why = check_threads(cmd.threads); !why.empty())
      throw UsageError(fmt::format("--resume: {}: threads: {}", file.string(), why));
    r.restore("--float32", "float32", cmd.float32);
    r.restore("--no-preview", "no_preview", cmd.pages.no_preview);
    r.restore("--no-report", "no_report", cmd.pages.no_report);
    r.restore("--no-plot", "no_plot", cmd.no_plot);
    restore_properties_outputs(r, cmd.properties);
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

// Stops a group's members with an exit code, for an error its rank 0 alone saw (reading or
// writing a member's folder), once the group has agreed on it.
struct GroupStop {
  int code = kExitFailure;
  std::string message;
};

// How the processes share the sweep (docs/scaling.md, "Sweeps across nodes"): `groups` groups
// of `group_ranks`, and the group of each member. One group of one process without mpirun.
struct GroupPlan {
  int groups = 1;
  int group_ranks = 1;
  std::vector<int> member_group;
};

// --groups, checked alike on every process before any communication.
GroupPlan plan_groups(const SweepCommand& cmd, const SweepParams& sp, const Decomposition& world) {
  const int ranks = world.ranks();
  auto problem = [&](int group_ranks) { return group_grid_problem(sp.run, group_ranks); };
  std::vector<int> accepted;
  for (int g = 1; g <= ranks; ++g)
    if (ranks % g == 0 && problem(ranks / g).empty()) accepted.push_back(g);
  const std::string accepted_text =
      fmt::format("accepted: 0 (automatic) or a divisor G of the {} process{} whose groups of {} "
                  "/ G processes split the grid: {}",
                  ranks, ranks == 1 ? "" : "es", ranks, fmt::join(accepted, ", "));
  GroupPlan plan;
  if (cmd.groups == 0) {
    plan.groups = default_groups(ranks, int(sweep_units(sp).size()),
                                 [&](int q) { return problem(q).empty(); });
  } else if (cmd.groups < 0 || cmd.groups > ranks || ranks % cmd.groups != 0) {
    throw UsageError(fmt::format("--groups {}: not a divisor of the {} process{}; {}", cmd.groups,
                                 ranks, ranks == 1 ? "" : "es", accepted_text));
  } else if (const std::string why = problem(ranks / cmd.groups); !why.empty()) {
    throw UsageError(
        fmt::format("--groups {}: a group of {} processes cannot run a member ({}); {}", cmd.groups,
                    ranks / cmd.groups, why, accepted_text));
  } else {
    plan.groups = cmd.groups;
  }
  plan.group_ranks = ranks / plan.groups;
  plan.member_group = assign_members(sp, plan.groups);
  return plan;
}

std::string member_name_at(const SweepParams& sp, int index) {
  const int f = int(sp.fractions.size());
  return member_name(sp.surfaces[std::size_t(index / f)], index / f,
                     sp.fractions[std::size_t(index % f)]);
}

// A new sweep into a folder an earlier sweep wrote: its figures, table and page go, and so do
// the member folders the new sweep does not have (their cmcsurf outputs; a folder that then
// holds someone else's files is kept and named). Members the new sweep has are cleared when
// they run.
void clear_earlier_sweep(const fs::path& dir, const SweepParams& sp) {
  for (const char* name : {"sweep.csv", "families.png", "families.svg", "gallery.png",
                           kPropertiesChartName, "report.html"}) {
    std::error_code ec;
    fs::remove(dir / name, ec);
    if (ec)
      throw std::runtime_error(fmt::format("cannot remove the earlier sweep's '{}': {}",
                                           (dir / name).string(), ec.message()));
  }
  std::vector<std::string> names;
  for (int i = 0; i < int(sp.surfaces.size() * sp.fractions.size()); ++i)
    names.push_back(member_name_at(sp, i));
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::path member = it->path();
    std::error_code is_dir;
    if (!it->is_directory(is_dir) || it->is_symlink(is_dir) || !is_cmcsurf_folder(member) ||
        std::find(names.begin(), names.end(), member.filename().string()) != names.end())
      continue;
    const FolderClaim claim = claim_output_folder(member, {.option = "an earlier member"});
    clear_run_outputs(member);
    remove_checkpoint(member / kCheckpointFileName);
    remove_stale_temporaries(member);
    if (!remove_folder_if_only_ours(member))
      std::cerr << fmt::format("note: kept the earlier sweep's member folder {}: it holds files "
                               "cmcsurf did not write\n",
                               member.string());
  }
}

void print_plan(const SweepParams& sp, const GroupPlan& plan, const Decomposition& group) {
  std::cerr << fmt::format(
      "sweep: {} members on {} processes in {} group{} of {} (process grid {} x {} x {} each)\n",
      plan.member_group.size(), plan.groups * plan.group_ranks, plan.groups,
      plan.groups == 1 ? "" : "s", plan.group_ranks, group.dims()[0], group.dims()[1],
      group.dims()[2]);
  for (int g = 0; g < plan.groups; ++g) {
    std::vector<std::string> names;
    for (int m = 0; m < int(plan.member_group.size()); ++m)
      if (plan.member_group[std::size_t(m)] == g) names.push_back(member_name_at(sp, m));
    std::cerr << fmt::format("  group {} (ranks {}-{}): {}\n", g, g * plan.group_ranks,
                             (g + 1) * plan.group_ranks - 1,
                             names.empty() ? std::string("nothing")
                                           : fmt::format("{}", fmt::join(names, ", ")));
  }
}

double number_in(const nlohmann::json& report, const char* key) {
  const auto it = report.find(key);
  return it != report.end() && it->is_number() ? it->get<double>() : NAN;
}

// print_member's line for a member another group ran, from its report.json.
void print_row(const nlohmann::json& r, int index, int count, int group) {
  const double area = number_in(r, "area"), nodal_area = number_in(r, "nodal_area");
  std::cerr << fmt::format(
      "[{}/{}] {} (group {}): {} steps, {:.1f} s: area {:.5f} H {:+.4f} (local std {:.3g}, nodal "
      "{:.3g}) nodal area excess {:+.3f}%{}\n",
      index + 1, count, r.value("member", "?"), group, number_in(r, "steps"),
      number_in(r, "wall_seconds"), area, number_in(r, "mean_curvature"),
      number_in(r, "mean_curvature_std"), number_in(r, "nodal_mean_curvature_std"),
      std::isfinite(nodal_area) ? 100.0 * (nodal_area / area - 1.0) : 0.0,
      r.value("converged", false) ? "" : " NOT converged");
}

std::vector<nlohmann::json> reports_of(const std::vector<GroupRows::Row>& rows) {
  std::vector<nlohmann::json> reports;
  for (const GroupRows::Row& row : rows) reports.push_back(row.report);
  return reports;
}

// One process runs every member; under mpirun each group of processes runs its members
// (decomposed over the group, its rank 0 writing their folders as `run` does) and world rank 0
// gathers the rows for sweep.csv, the figures and sweep.json.
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
  const GroupPlan gplan = plan_groups(cmd, sp, *world);
  refuse_if_too_large(sp.run, *world, gplan.group_ranks);  // before the folder is touched
  finish_properties_options(cmd.properties, sp.surfaces.front(), sp.run.grid);
  if (cmd.properties.stage.enabled && gplan.group_ranks > 1)
    throw UsageError(fmt::format(
        "--properties: the properties solvers hold a member's whole grid; with groups of {} "
        "processes they cannot run (use --groups {} for groups of one process, or `cmcsurf "
        "properties` on the members afterwards)",
        gplan.group_ranks, world->ranks()));
  const int threads = apply_threads(cmd.threads);
  cmd.threads = threads;  // the count in use, kept in sweep.json for a resume
  const auto t0 = std::chrono::steady_clock::now();
  const bool world_root = world->rank() == 0;
  const std::size_t members = sp.surfaces.size() * sp.fractions.size();
  auto summary_of = [&](std::size_t count, double wall) {
    nlohmann::json summary = sweep_summary(sp, cmd, count, threads, wall);
    if (world->distributed())
      summary["mpi"] = {{"ranks", world->ranks()},
                        {"groups", gplan.groups},
                        {"ranks_per_group", gplan.group_ranks}};
    return summary;
  };
  // World rank 0 prepares the folder; every process learns whether it could before any group
  // writes into it. sweep.json first, marked incomplete, so that an interrupted sweep can be
  // resumed.
  // One writer, and only into a folder that is ours (or new, or empty), before any work.
  const FolderClaim claim = claim_folder(
      dir, {.kind = "sweep", .option = resuming ? "--resume" : "--out", .force = cmd.force},
      *world);
  std::string setup_error;
  if (world_root) {
    try {
      remove_leftover_temporaries(dir, cmd.quiet);  // of an earlier process killed mid-write
      if (!resuming) {
        clear_earlier_sweep(dir, sp);
        nlohmann::json started = summary_of(members, 0);
        started["complete"] = false;
        write_json_atomic(dir / "sweep.json", started);
      }
    } catch (const std::exception& e) {
      setup_error = e.what();
    }
  }
  if (world->max_exit_code(setup_error.empty() ? 0 : kExitFailure) != 0) {
    if (world_root) std::cerr << "error: " << setup_error << "\n";
    return kExitFailure;
  }
  const ProcessGroup group = Decomposition::split(gplan.groups);
  const std::shared_ptr<const Decomposition> gd = group.decomposition;
  const bool group_root = gd->rank() == 0;
  if (world->distributed() && world_root && !cmd.quiet) print_plan(sp, gplan, *gd);
  std::string resume_cmd = fmt::format("{} sweep --resume {}", shell_quote(self_executable()),
                                       shell_quote(dir.string()));
  if (world->distributed())
    resume_cmd = fmt::format("mpirun -np {} {}", world->ranks(), resume_cmd);
  SignalGuard signals;
  CheckpointSink sink(dir, sp.run, output_options(cmd), cmd.checkpoints.every,
                      gd->distributed() ? gd : nullptr);
  SweepMember current;
  FolderClaim member_claim;  // the folder of the member this group's rank 0 writes
  GroupRows mine;  // the rows of this group's members (on its rank 0)
  Progress progress(cmd.quiet || !world_root);
  // An error one process of the group saw ends the group's members on all of them.
  auto agree = [&](int code, const std::string& failure) {
    if (gd->distributed()) code = gd->max_exit_code(code);
    if (code != 0) throw GroupStop{code, failure};
  };
  auto write_partial_csv = [&] {  // world rank 0, after each of its own members
    if (world_root) write_file_atomic(dir / "sweep.csv", sweep_csv(reports_of(mine.rows)));
  };
  auto starting = [&](const SweepMember& m) {
    if (!cmd.quiet && world_root)
      std::cerr << fmt::format("[{}/{}] {} alpha {} from {}\n", m.index + 1, m.count, m.surface,
                               m.alpha, m.started_from);
  };
  auto done = [&](const SweepMember& m, RunResult& r) {
    // As `cmcsurf run` does: every process of the group computes the outputs on its blocks
    // (the group's rank 0 gets the pictures) and writes its piece of field.pvti; the group's
    // rank 0 writes the rest. No process holds the whole grid (docs/scaling.md, "Output").
    std::string failure;
    std::optional<RunOutputs> outputs;
    PropertiesPicture youngs;  // youngs_modulus.png with --properties
    nlohmann::json extra = {{"volume_fraction_target", m.alpha},  // also if continued
                            {"member", m.name},
                            {"started_from", m.started_from}};
    if (world->distributed()) {
      extra.update(decomposition_json(*gd));
      extra.erase("mpi_rank0");  // the group's counters add up over its members
      extra["sweep_group"] = group.index;
    }
    double field_seconds = 0.0;
    try {
      // Quality, preview.png and report.html's meshes (docs/report.md).
      outputs = run_outputs(r.phi, m.params, r, !cmd.pages.no_preview, !cmd.pages.no_report);
      if (outputs->preview) extra["preview_seconds"] = outputs->preview->seconds;
      if (outputs->page) extra["page_seconds"] = outputs->page_seconds;
      if (cmd.properties.stage.enabled) {  // the member's solid (docs/properties.md)
        extra.update(run_properties_keys(r.phi, m.params.surface, cmd.properties.stage));
        if (group_root && !cmd.pages.no_preview) {  // the group's rank 0 draws the pictures
          youngs = youngs_modulus_picture(extra["properties"],
                                          properties_title(m.surface, extra["properties"]));
          if (!youngs.image.rgb.empty()) extra["youngs_picture_seconds"] = youngs.seconds;
        }
      }
      if (gd->distributed())  // field.pvti: one piece per process of the group
        field_seconds = write_run_field_pieces(dir / m.name, m.params, r, outputs->quality,
                                               threads, cmd.float32, extra);
    } catch (const std::exception& e) {
      failure = e.what();
    }
    if (group_root && failure.empty()) {
      try {
        const CmcQuality& quality = outputs->quality;
        std::optional<RunPreview>& preview = outputs->preview;
        GroupRows::Row row;
        row.index = m.index;
        row.report = write_run_folder(
            dir / m.name, m.params, r, gd->distributed() ? Field() : r.phi, quality, threads,
            cmd.float32, extra,
            [&](const nlohmann::json& report_to_be) {
              if (preview) write_png(dir / m.name / "preview.png", preview->image);
              if (!youngs.image.rgb.empty())
                write_png(dir / m.name / kYoungsPictureName, youngs.image);
              if (outputs->page) write_run_page(dir / m.name, &*outputs->page, &report_to_be);
            },
            field_seconds);
        remove_checkpoint(dir / m.name / kCheckpointFileName);  // the member is complete
        if (preview)
          row.tile = GalleryMember{m.surface, m.name, m.alpha, r.final.mean_curvature,
                                   std::move(preview->surfaces.relaxed)};
        mine.rows.push_back(std::move(row));
        write_partial_csv();
        progress.finish();
        if (!cmd.quiet && world_root) print_member(m, r, quality);
      } catch (const std::exception& e) {
        failure = e.what();
      }
    }
    agree(failure.empty() ? 0 : kExitFailure, failure);
  };
  // Each member's folder: kept when complete (resume), continued from its checkpoint, or
  // cleared of an earlier run's outputs. The group's rank 0 looks and tells the others.
  auto plan = [&](const SweepMember& m) {
    MemberStart start;
    if (gplan.member_group[std::size_t(m.index)] != group.index) {
      start.kind = MemberStart::Kind::kElsewhere;
      return start;
    }
    // One decision for the group: a signal any of its processes got stops it here.
    if (gd->max(SignalGuard::received() != 0 ? 1.0 : 0.0) > 0.0) throw StopBetweenMembers{};
    current = m;
    const fs::path mdir = dir / m.name;
    sink.retarget(mdir, m.params);
    enum Decision { kRun, kResume, kSkip, kFailed };
    int decision = kRun;
    std::string failure;
    nlohmann::json report;
    if (group_root) {
      try {
        // One writer per member folder too (a second sweep, a run pointed into it).
        member_claim = claim_output_folder(
            mdir, {.kind = "run", .option = "member folder", .force = cmd.force});
        remove_leftover_temporaries(mdir, cmd.quiet);
        if (resuming && fs::exists(mdir / kCheckpointFileName)) {
          decision = kResume;
        } else if (resuming && fs::exists(mdir / "report.json")) {
          report = read_json_file(mdir / "report.json");
          if (report.value("stop_reason", "") != "interrupted" &&
              (fs::exists(mdir / kRunFieldVti) || fs::exists(mdir / kRunFieldPvti)) &&
              report.value("parameters", nlohmann::json()) == params_json(m.params) &&
              report.value("started_from", "") == m.started_from)
            decision = kSkip;
        }
        if (decision == kRun) {
          clear_run_outputs(mdir);
          remove_checkpoint(mdir / kCheckpointFileName);
        }
      } catch (const std::exception& e) {
        decision = kFailed;
        failure = e.what();
      }
    }
    double told = decision;
    gd->broadcast(&told, 1);
    decision = int(told);
    agree(decision == kFailed ? kExitFailure : 0, failure);
    if (decision == kResume) {
      // A continued member goes on through relax_to_volume_fraction, the first of a family
      // through run_cmc (pipeline/sweep.h): the checkpoint must fit that run. Every process
      // of the group reads it and takes its blocks.
      const RunEntry entry =
          m.started_from == "nodal" ? RunEntry::kCmc : RunEntry::kRelaxToVolume;
      LoadedCheckpoint loaded =
          load_checkpoint(mdir, entry, gd->distributed() ? gd : nullptr);
      start.checkpoint = std::move(loaded.checkpoint);
      if (loaded.params != params_json(m.params))
        throw UsageError(fmt::format("--resume: {} belongs to a run with other parameters than "
                                     "the sweep's member {}",
                                     (mdir / kCheckpointFileName).string(), m.name));
      start.kind = MemberStart::Kind::kResume;
      ++mine.resumed;
      if (!cmd.quiet && world_root)
        std::cerr << fmt::format("[{}/{}] {}: resuming before step {} ({} on {}^3)\n",
                                 m.index + 1, m.count, m.name, start.checkpoint->step + 1,
                                 start.checkpoint->cursor.stage, start.checkpoint->cursor.grid);
      return start;
    }
    if (decision == kSkip) {
      start.kind = MemberStart::Kind::kSkip;
      if (sp.continuation)  // the whole field on every process; run_sweep takes its block
        start.field = std::move(
            read_field_file(run_field_file(mdir), VtiReadOptions{2, 1 << 13, "phi"})
                .arrays["phi"]);
      ++mine.kept;
      if (group_root) {
        try {
          GroupRows::Row row;
          row.index = m.index;
          row.report = std::move(report);
          // Its tile, so that gallery.png shows every member (as the uninterrupted sweep's).
          if (!cmd.pages.no_preview)
            row.tile = gallery_member_from_folder(mdir, m.surface, m.name, m.alpha);
          mine.rows.push_back(std::move(row));
          write_partial_csv();
        } catch (const std::exception& e) {
          failure = e.what();
        }
        if (!cmd.quiet && world_root && failure.empty())
          std::cerr << fmt::format("[{}/{}] {}: complete, kept\n", m.index + 1, m.count, m.name);
      }
      agree(failure.empty() ? 0 : kExitFailure, failure);
    }
    return start;
  };
  RunContext context([&](const StepRecord& s) { progress.step(s); });
  if (gd->distributed()) context.decomposition = gd;
  sink.attach(context);
  // A group that stops early says why: world rank 0 prints its own group's reason now and the
  // others' once it has gathered them.
  auto stopped = [&](int code, const std::string& message) {
    mine.status = code;
    if (world_root)
      std::cerr << message;
    else
      mine.message = message;
  };
  try {
    run_sweep(sp, starting, done, context, plan);
  } catch (RunInterrupted& stop) {
    progress.finish();
    mine.status = finish_interrupted(dir / current.name, current.params, stop, sink, threads,
                                     resume_cmd, cmd.quiet,
                                     {{"volume_fraction_target", current.alpha},
                                      {"member", current.name},
                                      {"started_from", current.started_from}});
    if (!world_root)  // world rank 0 printed it in finish_interrupted
      mine.message = fmt::format("interrupted in member {}, its checkpoint kept\n", current.name);
  } catch (const StopBetweenMembers&) {
    stopped(SignalGuard::exit_code(),
            fmt::format("\ninterrupted by a signal between members ({} complete)\n"
                        "resume with: {}\n",
                        mine.rows.size(), resume_cmd));
  } catch (const GroupStop& e) {
    stopped(e.code, fmt::format("error: {}\n", e.message));
  } catch (const UsageError& e) {
    stopped(kExitUsage, fmt::format("error: {}\n", e.what()));
  } catch (const SolverDiverged& e) {
    stopped(kExitFailure,
            fmt::format("error: the run diverged and was stopped; nothing was written.\n{}\n",
                        e.what()));
  } catch (const std::exception& e) {
    if (gd->distributed()) throw;  // perhaps on this process alone: run_main ends them all
    stopped(kExitFailure, fmt::format("error: {}\n", e.what()));
  }
  progress.finish();

  // World rank 0 gathers every group's rows (each group's rank 0 sends, the others send none).
  const std::vector<std::string> packed =
      gather_world_bytes(group_root ? pack_group_rows(mine) : std::string());
  if (!world_root) return mine.status;  // main agrees on the exit code over the world
  try {
    int status = 0, kept = 0, resumed = 0;
    std::vector<std::pair<int, GroupRows::Row>> rows;  // (group, row)
    for (std::size_t rank = 0; rank < packed.size(); ++rank) {
      if (packed[rank].empty()) continue;
      const int g = int(rank) / gplan.group_ranks;
      GroupRows from = g == group.index ? std::move(mine) : unpack_group_rows(packed[rank]);
      status = std::max(status, from.status);
      if (!from.message.empty()) std::cerr << fmt::format("group {}: {}", g, from.message);
      kept += from.kept;
      resumed += from.resumed;
      for (GroupRows::Row& row : from.rows) rows.emplace_back(g, std::move(row));
    }
    std::sort(rows.begin(), rows.end(),
              [](const auto& a, const auto& b) { return a.second.index < b.second.index; });
    std::vector<nlohmann::json> reports;
    std::vector<GalleryMember> gallery;
    for (auto& [g, row] : rows) {
      if (g != group.index && !cmd.quiet)
        print_row(row.report, row.index, int(members), g);
      reports.push_back(row.report);
      if (row.tile) gallery.push_back(std::move(*row.tile));
    }
    if (!reports.empty()) write_file_atomic(dir / "sweep.csv", sweep_csv(reports));
    if (status != 0) return status;
    if (reports.size() != members)
      throw std::logic_error(fmt::format("sweep: {} of {} members gathered", reports.size(),
                                         members));
    const double wall =
        seconds_since(t0);
    if (!cmd.no_plot) plot(cmd, dir);
    nlohmann::json summary = summary_of(reports.size(), wall);
    summary["complete"] = true;
    if (resuming) summary["resumed"] = {{"members_kept", kept}, {"members_resumed", resumed}};
    if (!gallery.empty()) summary["gallery_seconds"] = write_gallery(dir, gallery);
    // The designer's chart and its Gibson-Ashby fits.
    if (cmd.properties.stage.enabled && !cmd.no_plot) {
      const PropertiesChart chart = properties_chart(
          reports, fmt::format("{}: effective stiffness and conductivity",
                               (dir.filename().empty() ? dir.parent_path() : dir)
                                   .filename()
                                   .string()));
      if (!chart.image.rgb.empty()) {
        write_png(dir / kPropertiesChartName, chart.image);
        summary["properties_chart"] = {
            {"file", kPropertiesChartName}, {"seconds", chart.seconds}, {"fits", chart.fits},
            {"error_bars", chart.error_bars}};
      }
    }
    write_json_atomic(dir / "sweep.json", summary);
    if (!cmd.pages.no_report) write_sweep_page(dir);
    if (!cmd.quiet)
      std::cerr << fmt::format("sweep: {} members in {:.1f} s; wrote {}/sweep.csv{}\n",
                               reports.size(), wall, dir.string(),
                               fs::exists(dir / "families.png") ? ", families.png/.svg" : "");
    return 0;
  } catch (const std::exception& e) {  // world rank 0 alone: the others wait in main
    std::cerr << "error: " << e.what() << "\n";
    return kExitFailure;
  }
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
  app->add_option("--python", cmd->python, "Python with matplotlib for the figures")
      ->capture_default_str();
  app->add_option("--plot-script", cmd->plot_script, "Path of scripts/plot_families.py");
  add_force_option(*app, cmd->force);
  add_properties_options(*app, cmd->properties, "each member's");
  app->add_flag("--quiet", cmd->quiet, "No progress output");
  add_page_options(*app, cmd->pages);
  add_checkpoint_options(*app, cmd->checkpoints, true);
  return {app, [cmd, app]() -> int { return sweep(*cmd, *app); }};
}

}  // namespace cmcsurf::cli
