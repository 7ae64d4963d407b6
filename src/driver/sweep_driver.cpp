#include "driver/sweep_driver.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <optional>

#include "common/wall_clock.h"
#include "common/atomic_file.h"
#include "io/build_info.h"
#include "io/json_file.h"
#include "io/output_folder.h"
#include "io/png.h"
#include "io/pvti.h"
#include "io/run_folder.h"
#include "io/run_report.h"
#include "io/vti.h"
#include "driver/families_figure.h"
#include "pipeline/properties_pictures.h"
#include "model/run_options.h"
#include "pipeline/run_outputs.h"
#include "report/run_page.h"
#include "pipeline/sweep_groups.h"

namespace cmcsurf {

namespace {

namespace fs = std::filesystem;

constexpr int kFailed = 1;   // the command line's exit codes
constexpr int kRefused = 2;

// Stops a sweep between two members when a signal arrived while one was being written.
struct StopBetweenMembers {};

// Stops a group's members with an exit code, for an error its rank 0 alone saw (reading or
// writing a member's folder), once the group has agreed on it.
struct GroupStop {
  int code = kFailed;
  std::string message;
};

// A new sweep into a folder an earlier sweep wrote: its figures, table and page go, and so do
// the member folders the new sweep does not have (their cmcsurf outputs; a folder that then
// holds someone else's files is kept and named). Members the new sweep has are cleared when
// they run.
void clear_earlier_sweep(const fs::path& dir, const SweepParams& sp,
                         const std::function<void(const std::string&)>& note) {
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
    if (!remove_folder_if_only_ours(member) && note)
      note(fmt::format("note: kept the earlier sweep's member folder {}: it holds files "
                       "cmcsurf did not write\n",
                       member.string()));
  }
}

// The folder's own name ("runs/s/" gives "s").
std::string folder_name(const fs::path& dir) {
  return (dir.filename().empty() ? dir.parent_path() : dir).filename().string();
}

std::vector<nlohmann::json> reports_of(const std::vector<GroupRows::Row>& rows) {
  std::vector<nlohmann::json> reports;
  for (const GroupRows::Row& row : rows) reports.push_back(row.report);
  return reports;
}

std::string removed_note(int removed, const fs::path& dir) {
  return fmt::format("removed {} unfinished temporary file(s) an earlier process left in {}\n",
                     removed, dir.string());
}

}  // namespace

GroupPlan plan_groups(int groups, const SweepParams& sp, const Decomposition& world) {
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
  if (groups == 0) {
    plan.groups = default_groups(ranks, int(sweep_units(sp).size()),
                                 [&](int q) { return problem(q).empty(); });
  } else if (groups < 0 || groups > ranks || ranks % groups != 0) {
    throw OptionError(fmt::format("--groups {}: not a divisor of the {} process{}; {}", groups,
                                  ranks, ranks == 1 ? "" : "es", accepted_text));
  } else if (const std::string why = problem(ranks / groups); !why.empty()) {
    throw OptionError(
        fmt::format("--groups {}: a group of {} processes cannot run a member ({}); {}", groups,
                    ranks / groups, why, accepted_text));
  } else {
    plan.groups = groups;
  }
  plan.group_ranks = ranks / plan.groups;
  plan.member_group = assign_members(sp, plan.groups);
  return plan;
}

std::string describe_plan(const SweepParams& sp, const GroupPlan& plan,
                          const Decomposition& group) {
  std::string text = fmt::format(
      "sweep: {} members on {} processes in {} group{} of {} (process grid {} x {} x {} each)\n",
      plan.member_group.size(), plan.groups * plan.group_ranks, plan.groups,
      plan.groups == 1 ? "" : "s", plan.group_ranks, group.dims()[0], group.dims()[1],
      group.dims()[2]);
  for (int g = 0; g < plan.groups; ++g) {
    std::vector<std::string> names;
    for (int m = 0; m < int(plan.member_group.size()); ++m)
      if (plan.member_group[std::size_t(m)] == g) names.push_back(member_name_at(sp, m));
    text += fmt::format("  group {} (ranks {}-{}): {}\n", g, g * plan.group_ranks,
                        (g + 1) * plan.group_ranks - 1,
                        names.empty() ? std::string("nothing")
                                      : fmt::format("{}", fmt::join(names, ", ")));
  }
  return text;
}

std::string member_name_at(const SweepParams& sp, int index) {
  const int f = int(sp.fractions.size());
  return member_name(sp.surfaces[std::size_t(index / f)], index / f,
                     sp.fractions[std::size_t(index % f)]);
}

nlohmann::json sweep_summary(const SweepParams& sp, const nlohmann::json& outputs,
                             std::size_t members, int threads, double wall) {
  nlohmann::json summary = {{"members", members},
                            {"surfaces", sp.surfaces},
                            {"volume_fractions", sp.fractions},
                            {"continuation", sp.continuation},
                            {"threads", threads},
                            {"wall_seconds", wall},
                            {"version", std::string(CMCSURF_VERSION)},
                            {"build", build_info_json()},
                            {"parameters", params_json(sp.run)},
                            {"outputs", outputs}};
  summary["parameters"].erase("surface");  // per member
  summary["parameters"].erase("volume_fraction");
  return summary;
}

nlohmann::json sweep_outputs_json(const SweepJob& job, const std::string& porosity) {
  nlohmann::json outputs = {{"threads", job.member.threads},
                            {"float32", job.member.float32},
                            {"no_preview", !job.preview},
                            {"no_report", !job.page},
                            {"no_plot", !job.figures},
                            {"plot_diffuse", job.diffuse},
                            {"checkpoint_every", job.checkpoint_every}};
  outputs.update(properties_outputs_json(job.member.properties, porosity));
  return outputs;
}

// One process runs every member; under mpirun each group of processes runs its members
// (decomposed over the group, its rank 0 writing their folders as `run` does) and world rank 0
// gathers the rows for sweep.csv, the figures and sweep.json.
SweepOutcome drive_sweep(const SweepJob& job, const SweepHooks& hooks) {
  const SweepParams& sp = job.sweep;
  const GroupPlan& gplan = job.plan;
  const fs::path& dir = job.dir;
  const bool resuming = job.resuming;
  const int threads = job.member.threads;
  const auto world = Decomposition::world();
  const auto t0 = std::chrono::steady_clock::now();
  const bool world_root = world->rank() == 0;
  const std::size_t members = sp.surfaces.size() * sp.fractions.size();
  SweepOutcome outcome;
  auto say = [&](const std::function<void(const std::string&)>& hook, const std::string& s) {
    if (hook) hook(s);
  };
  auto summary_of = [&](std::size_t count, double wall) {
    nlohmann::json summary = sweep_summary(sp, job.outputs, count, threads, wall);
    if (world->distributed())
      summary["mpi"] = {{"ranks", world->ranks()},
                        {"groups", gplan.groups},
                        {"ranks_per_group", gplan.group_ranks}};
    return summary;
  };
  // World rank 0 prepares the folder; every process learns whether it could before any group
  // writes into it. sweep.json first, marked incomplete, so that an interrupted sweep can be
  // resumed.
  std::string setup_error;
  if (world_root) {
    try {
      // Of an earlier process killed mid-write.
      if (const int removed = remove_stale_temporaries(dir); removed > 0)
        say(hooks.note, removed_note(removed, dir));
      if (!resuming) {
        clear_earlier_sweep(dir, sp, hooks.notice);
        nlohmann::json started = summary_of(members, 0);
        started["complete"] = false;
        write_json_atomic(dir / "sweep.json", started);
      }
    } catch (const std::exception& e) {
      setup_error = e.what();
    }
  }
  if (world->max_exit_code(setup_error.empty() ? 0 : kFailed) != 0) {
    if (world_root) say(hooks.error, fmt::format("error: {}\n", setup_error));
    outcome.exit_code = kFailed;
    return outcome;
  }
  const ProcessGroup group = Decomposition::split(gplan.groups);
  const std::shared_ptr<const Decomposition> gd = group.decomposition;
  const bool group_root = gd->rank() == 0;
  if (world->distributed() && world_root && hooks.note)
    hooks.note(describe_plan(sp, gplan, *gd));
  CheckpointSink sink(dir, sp.run, job.outputs, job.checkpoint_every,
                      gd->distributed() ? gd : nullptr, hooks.stop_requested, hooks.warning);
  SweepMember current;
  FolderClaim member_claim;  // the folder of the member this group's rank 0 writes
  GroupRows mine;            // the rows of this group's members (on its rank 0)
  auto stop_requested = [&] { return hooks.stop_requested && hooks.stop_requested(); };
  auto steps_done = [&] {
    if (hooks.steps_done) hooks.steps_done();
  };
  // An error one process of the group saw ends the group's members on all of them.
  auto agree = [&](int code, const std::string& failure) {
    if (gd->distributed()) code = gd->max_exit_code(code);
    if (code != 0) throw GroupStop{code, failure};
  };
  auto write_partial_csv = [&] {  // world rank 0, after each of its own members
    if (world_root) write_file_atomic(dir / "sweep.csv", sweep_csv(reports_of(mine.rows)));
  };
  auto starting = [&](const SweepMember& m) {
    if (world_root && hooks.starting) hooks.starting(m);
  };
  auto done = [&](const SweepMember& m, const RunResult r, FinalFieldCache cache) {
    // As `cmcsurf run` does: every process of the group computes the outputs on its blocks
    // (the group's rank 0 gets the pictures) and writes its piece of field.pvti; the group's
    // rank 0 writes the rest. No process holds the whole grid (docs/scaling.md, "Output").
    std::string failure;
    nlohmann::json extra = {{"volume_fraction_target", m.alpha},  // also if continued
                            {"member", m.name},
                            {"started_from", m.started_from}};
    if (world->distributed()) {
      extra.update(decomposition_json(*gd));
      extra.erase("mpi_rank0");  // the group's counters add up over its members
      extra["sweep_group"] = group.index;
    }
    try {
      // Quality, preview.png and report.html's meshes (docs/report.md), then the folder.
      RunOutputs outputs =
          run_outputs(r.phi, m.params, r, std::move(cache), job.preview, job.page);
      std::optional<GalleryMember> tile;
      if (outputs.preview)
        tile = GalleryMember{m.surface, m.name, m.alpha, r.final.mean_curvature,
                             outputs.preview->surfaces.relaxed};
      RunFolderOptions o = job.member;
      o.pictures = job.preview;
      const FinishedRun finished = finish_run_folder(dir / m.name, m.params, r, outputs, o,
                                                     std::move(extra));
      if (finished.writer) {
        if (hooks.result) hooks.result(m, r, outputs.quality, finished.report);
        GroupRows::Row row;
        row.index = m.index;
        row.report = finished.report;
        row.tile = std::move(tile);
        mine.rows.push_back(std::move(row));
        write_partial_csv();
        steps_done();
        if (world_root && hooks.finished) hooks.finished(m, mine.rows.back().report);
      }
    } catch (const std::exception& e) {
      failure = e.what();
    }
    agree(failure.empty() ? 0 : kFailed, failure);
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
    if (gd->max(stop_requested() ? 1.0 : 0.0) > 0.0) throw StopBetweenMembers{};
    current = m;
    const fs::path mdir = dir / m.name;
    sink.retarget(mdir, m.params);
    MemberDecision decision;
    if (group_root) {
      int removed = 0;
      decision = decide_member(mdir, m, resuming, job.force, member_claim, &removed);
      if (removed > 0) say(hooks.note, removed_note(removed, mdir));
    }
    using Kind = MemberDecision::Kind;
    agree_member_decision(*gd, decision);
    agree(decision.kind == Kind::kFailed ? kFailed : 0, decision.failure);
    if (decision.kind == Kind::kResume) {
      // A continued member goes on through relax_to_volume_fraction, the first of a family
      // through run_cmc (pipeline/sweep.h): the checkpoint must fit that run. Every process
      // of the group reads it and takes its blocks.
      const RunEntry entry =
          m.started_from == "nodal" ? RunEntry::kCmc : RunEntry::kRelaxToVolume;
      LoadedCheckpoint loaded = load_checkpoint(mdir, entry, gd->distributed() ? gd : nullptr);
      start.checkpoint = std::move(loaded.checkpoint);
      if (loaded.params != params_json(m.params))
        throw OptionError(fmt::format("--resume: {} belongs to a run with other parameters than "
                                      "the sweep's member {}",
                                      (mdir / kCheckpointFileName).string(), m.name));
      start.kind = MemberStart::Kind::kResume;
      ++mine.resumed;
      if (world_root && hooks.resuming) hooks.resuming(m, *start.checkpoint);
      return start;
    }
    if (decision.kind == Kind::kSkip) {
      start.kind = MemberStart::Kind::kSkip;
      if (sp.continuation)  // the whole field on every process; run_sweep takes its block
        start.field = std::move(
            read_field_file(run_field_file(mdir), VtiReadOptions{2, 1 << 13, "phi"})
                .arrays["phi"]);
      ++mine.kept;
      std::string failure;
      if (group_root) {
        try {
          GroupRows::Row row;
          row.index = m.index;
          row.report = std::move(decision.report);
          // Its tile, so that gallery.png shows every member (as the uninterrupted sweep's).
          if (job.preview) row.tile = gallery_member_from_folder(mdir, m.surface, m.name, m.alpha);
          mine.rows.push_back(std::move(row));
          write_partial_csv();
        } catch (const std::exception& e) {
          failure = e.what();
        }
        if (world_root && failure.empty() && hooks.kept)
          hooks.kept(m, mine.rows.back().report);
      }
      agree(failure.empty() ? 0 : kFailed, failure);
    }
    return start;
  };
  RunContext context([&](const StepRecord& s) {
    if (hooks.step) hooks.step(s);
  });
  if (gd->distributed()) context.decomposition = gd;
  sink.attach(context);
  // A group that stops early says why: world rank 0 says its own group's reason now and the
  // others' once it has gathered them.
  auto stopped = [&](int code, const std::string& message) {
    mine.status = code;
    if (world_root)
      say(hooks.error, message);
    else
      mine.message = message;
  };
  auto stop_code = [&] { return hooks.stop_code ? hooks.stop_code() : 130; };
  try {
    run_sweep(sp, starting, done, context, plan);
  } catch (RunInterrupted& stop) {
    steps_done();
    const fs::path mdir = dir / current.name;
    const InterruptedRun left = write_interrupted_run(
        mdir, current.params, stop, sink, threads, job.resume_command,
        hooks.signal_name ? hooks.signal_name() : "a signal",
        {{"volume_fraction_target", current.alpha},
         {"member", current.name},
         {"started_from", current.started_from}});
    mine.status = left.failure.empty() ? stop_code() : kFailed;
    if (hooks.interrupted) hooks.interrupted(mdir, stop.checkpoint, left);
    if (!world_root)  // world rank 0 said it in `interrupted`
      mine.message = fmt::format("interrupted in member {}, its checkpoint kept\n", current.name);
  } catch (const StopBetweenMembers&) {
    stopped(stop_code(),
            fmt::format("\ninterrupted by a signal between members ({} complete)\n"
                        "resume with: {}\n",
                        mine.rows.size(), job.resume_command));
  } catch (const GroupStop& e) {
    stopped(e.code, fmt::format("error: {}\n", e.message));
  } catch (const OptionError& e) {
    stopped(kRefused, fmt::format("error: {}\n", e.what()));
  } catch (const SolverDiverged& e) {
    stopped(kFailed,
            fmt::format("error: the run diverged and was stopped; nothing was written.\n{}\n",
                        e.what()));
  } catch (const std::exception& e) {
    if (gd->distributed()) throw;  // perhaps on this process alone: the caller ends them all
    stopped(kFailed, fmt::format("error: {}\n", e.what()));
  }
  steps_done();

  // World rank 0 gathers every group's rows (each group's rank 0 sends, the others send none).
  const std::vector<std::string> packed =
      gather_world_bytes(group_root ? pack_group_rows(mine) : std::string());
  if (!world_root) {  // the caller agrees on the exit code over the world
    outcome.exit_code = mine.status;
    return outcome;
  }
  try {
    int status = 0, kept = 0, resumed = 0;
    std::vector<std::pair<int, GroupRows::Row>> rows;  // (group, row)
    for (std::size_t rank = 0; rank < packed.size(); ++rank) {
      if (packed[rank].empty()) continue;
      const int g = int(rank) / gplan.group_ranks;
      GroupRows from = g == group.index ? std::move(mine) : unpack_group_rows(packed[rank]);
      status = std::max(status, from.status);
      if (!from.message.empty()) say(hooks.error, fmt::format("group {}: {}", g, from.message));
      kept += from.kept;
      resumed += from.resumed;
      for (GroupRows::Row& row : from.rows) rows.emplace_back(g, std::move(row));
    }
    std::sort(rows.begin(), rows.end(),
              [](const auto& a, const auto& b) { return a.second.index < b.second.index; });
    std::vector<nlohmann::json> reports;
    std::vector<GalleryMember> gallery;
    for (auto& [g, row] : rows) {
      if (g != group.index && hooks.gathered) hooks.gathered(row.report, row.index,
                                                             int(members), g);
      reports.push_back(row.report);
      if (row.tile) gallery.push_back(std::move(*row.tile));
    }
    if (!reports.empty()) write_file_atomic(dir / "sweep.csv", sweep_csv(reports));
    outcome.members = reports.size();
    if (status != 0) {
      outcome.exit_code = status;
      return outcome;
    }
    if (reports.size() != members)
      throw std::logic_error(fmt::format("sweep: {} of {} members gathered", reports.size(),
                                         members));
    const double wall = seconds_since(t0);
    outcome.wall_seconds = wall;
    nlohmann::json summary = summary_of(reports.size(), wall);
    summary["complete"] = true;
    if (resuming) summary["resumed"] = {{"members_kept", kept}, {"members_resumed", resumed}};
    summary["literature"] = literature_json();
    if (job.figures)  // families.png and its SVG twin
      if (nlohmann::json f = write_families_figure(dir, reports, job.diffuse); !f.is_null())
        summary["families_figure"] = std::move(f);
    if (!gallery.empty()) summary["gallery_seconds"] = write_gallery(dir, gallery);
    // The designer's chart and its Gibson-Ashby fits.
    if (job.member.properties.enabled && job.figures) {
      const PropertiesChart chart = properties_chart(
          reports, fmt::format("{}: effective stiffness and conductivity", folder_name(dir)));
      if (!chart.image.rgb.empty()) {
        write_png(dir / kPropertiesChartName, chart.image);
        summary["properties_chart"] = {
            {"file", kPropertiesChartName}, {"seconds", chart.seconds}, {"fits", chart.fits},
            {"error_bars", chart.error_bars}};
      }
    }
    write_json_atomic(dir / "sweep.json", summary);
    if (job.page) write_sweep_page(dir);
    outcome.families_figure = fs::exists(dir / "families.png");
    return outcome;
  } catch (const std::exception& e) {  // world rank 0 alone: the others wait in the caller
    say(hooks.error, fmt::format("error: {}\n", e.what()));
    outcome.exit_code = kFailed;
    return outcome;
  }
}

}  // namespace cmcsurf
