// cmcsurf run: one CMC surface (Section 4.4) or a direct relaxation (sphere, cube, noise).
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <iostream>

#include "common/wall_clock.h"
#include "cli_common.h"
#include "commands.h"
#include "common/atomic_file.h"
#include "io/json_file.h"
#include "io/png.h"
#include "io/run_report.h"
#include "io/pvti.h"
#include "io/run_folder.h"
#include "io/vti.h"
#include "mesh_options.h"
#include "multigrid/fas.h"
#include "parallel/decomposition.h"
#include "pipeline/distributed_mesh.h"
#include "model/option_checks.h"
#include "pipeline/preview.h"
#include "pipeline/properties_pictures.h"
#include "pipeline/properties_stage.h"
#include "driver/run_finish.h"
#include "pipeline/run_outputs.h"
#include "pipeline/sweep.h"
#include "page_options.h"
#include "properties_options.h"
#include "report/run_page.h"
#include "run_control.h"
#include "schema/report_schema.h"

namespace cmcsurf::cli {

namespace {

struct RunCommand {
  RunParams params;
  RunOptionStrings strings;
  int threads = 0;
  std::string out = "cmcsurf-out";
  bool quiet = false;
  bool float32 = false;
  std::string mesh_format;  // empty: no surface mesh
  PageOptions pages;        // --no-preview, --no-report
  CheckpointOptions checkpoints;  // --checkpoint-every, --resume
  bool force = false;             // --force: a non-empty folder cmcsurf did not write
  PropertiesOptions properties;   // --properties, --properties-*: stiffness and conductivity
};

// Refuses, on every process alike and before any communication, what a split grid cannot do.
void check_decomposable(const RunParams& p, const Decomposition& world) {
  if (p.smoother != SweepOrder::kRedBlack)
    throw UsageError(fmt::format(
        "--smoother lex: a lexicographic Gauss-Seidel sweep depends on how the grid is split, so "
        "it is refused under mpirun ({} ranks); use --smoother redblack, whose result does not "
        "depend on the decomposition",
        world.ranks()));
  if (const std::string why = world.check_grid(p.grid); !why.empty())
    throw UsageError("--grid: " + why);
  for (int k = 1; k <= p.coarse_levels && check_coarsenable(p.grid >> k).empty(); ++k)
    if (const std::string why = world.check_grid(p.grid >> k); !why.empty())
      throw UsageError(
          fmt::format("--coarse-levels {}: the grid of level {}: {}", p.coarse_levels, k, why));
}

// How to continue an interrupted run in dir: this executable (under mpirun with as many
// processes) and --resume.
std::string resume_command(const std::filesystem::path& dir, const Decomposition& world) {
  const std::string cmd =
      fmt::format("{} run --resume {}", shell_quote(self_executable()), shell_quote(dir.string()));
  return world.distributed() ? fmt::format("mpirun -np {} {}", world.ranks(), cmd) : cmd;
}

void check_mesh_format(const std::string& format) {
  if (format.empty()) return;
  try {
    parse_mesh_format(format);
  } catch (const std::invalid_argument& e) {
    throw UsageError(fmt::format("--mesh: {}", e.what()));
  }
}

void validate(RunCommand& cmd) {
  finish_run_options(cmd.params, cmd.strings, true);
  const std::filesystem::path dir(cmd.out);
  if (std::filesystem::exists(dir) && !std::filesystem::is_directory(dir))
    throw UsageError(fmt::format("--out: '{}' exists and is not a directory", cmd.out));
  check_mesh_format(cmd.mesh_format);
}

// What the run writes besides the fields, and its thread count (OpenMP's reductions add in
// another order on another count), kept in its checkpoints: `run --resume DIR` alone writes
// the folder the uninterrupted run would have written.
nlohmann::json output_options(const RunCommand& cmd) {
  nlohmann::json outputs = {{"threads", cmd.threads},
                             {"float32", cmd.float32},
                             {"mesh", cmd.mesh_format},
                             {"no_preview", cmd.pages.no_preview},
                             {"no_report", cmd.pages.no_report},
                             {"checkpoint_every", cmd.checkpoints.every}};
  add_properties_outputs(outputs, cmd.properties);
  return outputs;
}

// --resume: the output options the run started with, unless given again.
void restore_output_options(RunCommand& cmd, const CLI::App& app, const nlohmann::json& saved,
                            const std::filesystem::path& file) {
  const OutputRestorer r(app, saved, file);
  r.restore("--threads", "threads", cmd.threads);
  if (const std::string why = check_threads(cmd.threads); !why.empty())
    throw UsageError(fmt::format("--resume: {}: threads: {}", file.string(), why));
  r.restore("--float32", "float32", cmd.float32);
  r.restore("--mesh", "mesh", cmd.mesh_format);
  r.restore("--no-preview", "no_preview", cmd.pages.no_preview);
  r.restore("--no-report", "no_report", cmd.pages.no_report);
  restore_properties_outputs(r, cmd.properties);
  r.restore("--checkpoint-every", "checkpoint_every", cmd.checkpoints.every);
  check_mesh_format(cmd.mesh_format);
  if (!(cmd.checkpoints.every >= 0.0 && cmd.checkpoints.every <= 1e9))
    throw UsageError(fmt::format("--resume: {}: checkpoint_every {} outside [0, 1e9]",
                                 file.string(), cmd.checkpoints.every));
}

// 1 - chi is the surface's genus only when both phases are connected (a double structure's
// phase 1 is two networks); -1 components: not counted (a decomposed grid), as before.
std::string genus_text(const Measures& m) {
  if (m.components_phase1 > 1 || m.components_phase2 > 1)
    return fmt::format("{} and {} components of phase 1 and 2: no single genus",
                       m.components_phase1, m.components_phase2);
  return fmt::format("genus {}", 1 - m.euler_characteristic);
}

// The numbers in the formats of the report key table (schema/report_schema.h, summary).
void print_summary(const RunParams& p, const RunResult& r, const CmcQuality& quality,
                   const nlohmann::json& report, const std::filesystem::path& dir) {
  auto number = [](const char* key, double x) { return summary_number(key, x); };
  std::cerr << fmt::format(
      "{} after {} steps ({} V-cycles, {} V-cycles/step, {} ms/V-cycle) in {} s\n",
      r.converged ? "converged" : "NOT converged (max-steps reached)", r.steps, r.vcycles,
      number("vcycles_per_step", report["vcycles_per_step"].get<double>()),
      number("seconds_per_vcycle", 1e3 * report["seconds_per_vcycle"].get<double>()),
      number("wall_seconds", r.wall_seconds));
  std::cerr << fmt::format(
      "area {}{}  mean curvature {}{} (from mu {})  volume fraction {}\n"
      "local H std {}{}  diffuse layer: area {} H {}  (measures {} s, quality {} s)\n"
      "phase 1: Euler characteristic {} ({}) per unit cell\nwrote "
      "{}/report.json, history.csv, {}\n",
      number("area", r.final.area), plus_minus(r.final.area_error),
      number("mean_curvature", r.final.mean_curvature), plus_minus(r.final.mean_curvature_error),
      number("mean_curvature_mu", r.final.mean_curvature_mu),
      number("volume_fraction", r.final.volume_fraction),
      number("mean_curvature_std", quality.relaxed.std),
      quality.has_nodal
          ? fmt::format(" (nodal {})", number("nodal_mean_curvature_std", quality.nodal.std))
          : "",
      number("area_diffuse", r.final.area_diffuse),
      number("mean_curvature_diffuse", r.final.mean_curvature_diffuse),
      number("measure_seconds", r.measure_seconds), number("quality_seconds", quality.seconds),
      r.final.euler_characteristic, genus_text(r.final), dir.string(),
      report.value("mpi_ranks", 1) > 1 ? "field.pvti (field/: one piece per process)"
                                       : "field.vti");
  if (p.epsilon * p.grid < 1.0) {  // docs/method.md, "Sharp measures": where they are weak
    int finer = p.grid;
    while (p.epsilon * finer < 1.28) finer *= 2;
    std::cerr << fmt::format(
        "note: epsilon = {:.2f} h under-resolves the interface, so the curvature figures are "
        "good to a few % only (see the +- estimates); --epsilon {:.3g} or --grid {} resolves "
        "it (epsilon >= 1.28 h)\n",
        p.epsilon * p.grid, 1.28 / p.grid, finer);
  }
}

void print_warnings(const RunParams& p, const RunResult& r) {
  if (r.unconverged_steps > 0)
    std::cerr << fmt::format("warning: {} time steps ended at --max-vcycles before --mg-tol\n",
                             r.unconverged_steps);
  if (r.volume_constrained && !r.volume_converged)
    std::cerr << fmt::format(
        "warning: the volume fraction {:.6f} is not within --volume-tol of {} after {} mass "
        "corrections (report.json volume_iterates); try a smaller --tol\n",
        r.final.volume_fraction, p.volume_fraction,
        r.volume_iterates.empty() ? 0 : int(r.volume_iterates.size()) - 1);
  for (const std::string& w : r.warnings) std::cerr << "warning: " << w << "\n";
}

// After a failure past the solve (no report.json was written, so the folder reads as
// incomplete): the solved field as field.vti, if it is not there yet, and where it is.
void keep_solved_field(const std::filesystem::path& dir, const RunParams& p, const RunResult& r,
                       int threads, bool float32) {
  try {
    if (!std::filesystem::exists(dir / kRunFieldVti))
      write_run_field(dir, {{"phi", &r.phi}}, float32,
                      run_field_metadata(p, r, run_report(p, r, threads)));
    std::cerr << fmt::format(
        "note: the solved field is kept in {} (the folder has no report.json: its outputs are "
        "incomplete); `cmcsurf mesh --from` reads it\n",
        (dir / kRunFieldVti).string());
  } catch (const std::exception& e) {
    std::cerr << fmt::format("note: the solved field could not be kept either: {}\n", e.what());
  }
}

int run(RunCommand& cmd, const CLI::App& app) {
  const bool resuming = !cmd.checkpoints.resume.empty();
  if (resuming) {
    if (app.count("--out") && std::filesystem::path(cmd.out) != cmd.checkpoints.resume)
      throw UsageError(
          fmt::format("--out {}: a resumed run writes into its own folder, --resume {}", cmd.out,
                      cmd.checkpoints.resume));
    cmd.out = cmd.checkpoints.resume;
  }
  validate(cmd);
  RunParams& p = cmd.params;
  const std::filesystem::path dir(cmd.out);
  const auto world = Decomposition::world();
  std::shared_ptr<const Checkpoint> resume;
  if (resuming && !std::filesystem::exists(dir / kCheckpointFileName))
    throw UsageError(fmt::format(
        "--resume {}: no {} there ({})", dir.string(), kCheckpointFileName,
        std::filesystem::exists(dir / "report.json") ? "the run completed, or was started with "
                                                       "--checkpoint-every 0 and killed"
                                                     : "not a run folder"));
  finish_properties_options(cmd.properties, p.surface, p.grid);
  if (cmd.properties.stage.enabled && world->distributed())
    throw UsageError(fmt::format("--properties: the properties solvers hold the whole grid, "
                                 "so they run on one process, not under mpirun ({} ranks): "
                                 "run `cmcsurf properties --from DIR` afterwards",
                                 world->ranks()));
  if (!resuming) {
    // Every option is checked before the folder is claimed (claiming may create it).
    if (world->distributed()) check_decomposable(p, *world);
  }
  // A grid that cannot fit is refused now, not after the solve (every process checks its own).
  if (!resuming) refuse_if_too_large(p, *world);
  // One writer per folder, and only a folder that is ours (or new, or empty): before any work,
  // and before a resume reads the checkpoint another writer might be replacing.
  const FolderClaim claim = claim_folder(
      dir, {.kind = "run", .option = resuming ? "--resume" : "--out", .force = cmd.force}, *world);
  if (resuming) {
    LoadedCheckpoint loaded =
        as_usage([&] { return load_checkpoint(dir, RunEntry::kCmc, world); });
    p = resumed_params(cmd.strings, p, loaded.params, dir / kCheckpointFileName);
    restore_output_options(cmd, app, loaded.outputs, dir / kCheckpointFileName);
    finish_properties_options(cmd.properties, p.surface, p.grid);  // the resumed grid's
    resume = std::move(loaded.checkpoint);
    if (world->distributed()) check_decomposable(p, *world);
    refuse_if_too_large(p, *world);
  }
  // Everything is checked: from here on the folder may change (it is ours: claim_folder).
  if (!resuming && world->rank() == 0) {
    clear_run_outputs(dir);  // an earlier run's report must not sit beside this one's files
    remove_checkpoint(dir / kCheckpointFileName);  // checkpoint.bin, then checkpoint.parts/
  }
  if (world->rank() == 0)
    remove_leftover_temporaries(dir, cmd.quiet);  // of an earlier process killed mid-write
  Progress progress(cmd.quiet);
  RunContext context([&](const StepRecord& s) { progress.step(s); });
  context.resume = resume;
  if (world->distributed()) context.decomposition = world;
  SignalGuard signals;
  const int threads = apply_threads(cmd.threads);
  cmd.threads = threads;  // the count in use, for the checkpoints
  CheckpointSink sink =
      signal_checkpoint_sink(dir, p, output_options(cmd), cmd.checkpoints.every, world);
  sink.attach(context);
  if (!cmd.quiet)
    std::cerr << fmt::format(
        "cmcsurf {}: surface {} alpha {} N {} epsilon {} dt {:.3g} threads {}{}\n",
        version_string(), p.surface, p.volume_fraction, p.grid, p.epsilon, p.dt(), threads,
        world->distributed() ? fmt::format(" x {} ranks ({} x {} x {})", world->ranks(),
                                           world->dims()[0], world->dims()[1], world->dims()[2])
                             : std::string());
  if (resume && !cmd.quiet)
    std::cerr << fmt::format("resuming {} before step {} ({} on {}^3, {:.1f} s done)\n",
                             dir.string(), resume->step + 1, run_stage_name(resume->cursor.stage),
                             resume->cursor.grid, resume->elapsed);
  RunResult r;
  FinalFieldCache cache;  // the final measures' psi and samples, for run_outputs
  try {
    r = run_cmc(p, context, &cache);
  } catch (RunInterrupted& stop) {
    progress.finish();
    return finish_interrupted(dir, p, stop, sink, threads, resume_command(dir, *world),
                              cmd.quiet, decomposition_json(*world));
  }
  progress.finish();

  try {
    // Every process measures, draws and meshes on its own block; the reductions give every
    // process the same numbers and rank 0 the pictures and the mesh. No process holds the whole
    // grid (docs/scaling.md, "Output").
    RunOutputs outputs = run_outputs(r.phi, p, r, std::move(cache), !cmd.pages.no_preview,
                                     !cmd.pages.no_report);
    nlohmann::json extra;
    extra["checkpoints_written"] = sink.written();
    extra["checkpoint_seconds"] = sink.seconds();
    if (resume) extra["resumed_from_step"] = resume->step;
    RunFolderOptions o;
    o.threads = threads;
    o.float32 = cmd.float32;
    o.pictures = !cmd.pages.no_preview;
    o.mesh_format = cmd.mesh_format;
    o.properties = cmd.properties.stage;
    o.layout = world.get();
    const FinishedRun finished = finish_run_folder(dir, p, r, outputs, o, std::move(extra));
    if (!finished.writer) return 0;
    const CmcQuality& quality = outputs.quality;
    const nlohmann::json& report = finished.report;
    if (!cmd.quiet) print_summary(p, r, quality, report, dir);
    print_warnings(p, r);
  } catch (const std::exception&) {
    // A late failure (memory, disk) must not lose the solve: keep the field for `mesh --from`.
    if (!world->distributed()) keep_solved_field(dir, p, r, threads, cmd.float32);
    throw;
  }
  if (SignalGuard::received()) {  // after the last step: the outputs were finished first
    std::cerr << "note: a signal arrived after the solve; the run folder is complete\n";
    return SignalGuard::exit_code();
  }
  return 0;
}

}  // namespace

CommandFn add_run_command(CLI::App& root) {
  auto cmd = std::make_shared<RunCommand>();
  CLI::App* app = root.add_subcommand(
      "run", "Compute one triply periodic CMC surface at a prescribed volume fraction");
  add_run_options(*app, cmd->params, cmd->strings, true);
  add_threads_option(*app, cmd->threads);
  app->add_option(
         "--out", cmd->out,
         "Output directory (report.json, history.csv, field.vti; field.pvti with one piece per "
         "process under mpirun)")
      ->capture_default_str()
      ->check(non_empty_text(), "DIR");
  app->add_flag("--float32", cmd->float32,
                "Write the field (field.vti or field.pvti) in single precision");
  app->add_option("--mesh", cmd->mesh_format,
                  "Also write the phi = 1/2 surface mesh as surface.FORMAT (stl|ply|obj|3mf), in "
                  "unit-cell coordinates, with surface.FORMAT.json")
      ->check(non_empty_text(), "FORMAT");
  app->add_flag("--quiet", cmd->quiet, "No progress output");
  add_page_options(*app, cmd->pages);
  add_checkpoint_options(*app, cmd->checkpoints, true);
  add_force_option(*app, cmd->force);
  add_properties_options(*app, cmd->properties, "the run's");
  return {app, [cmd, app]() -> int { return run(*cmd, *app); }};
}

}  // namespace cmcsurf::cli
