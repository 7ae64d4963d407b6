// cmcsurf merge: sweeps computed apart in one sweep folder (docs/families.md).
#include <fmt/format.h>

#include <filesystem>
#include <iostream>

#include "cli_common.h"
#include "commands.h"
#include "driver/sweep_merge.h"
#include "run_control.h"

namespace cmcsurf::cli {

namespace {

namespace fs = std::filesystem;

struct MergeCommand {
  std::vector<std::string> sources;
  std::string out;
  bool no_plot = false;
  bool plot_diffuse = false;
  bool no_report = false;
  bool force = false;
  bool quiet = false;
};

int merge(const MergeCommand& cmd) {
  std::vector<fs::path> sources(cmd.sources.begin(), cmd.sources.end());
  std::error_code ec;
  for (const fs::path& s : sources)
    if (fs::exists(cmd.out) && fs::equivalent(s, cmd.out, ec))
      throw UsageError(fmt::format("--out {}: is the source {}; accepted: a new folder",
                                   cmd.out, s.string()));
  const MergePlan plan = as_usage([&] { return plan_merge(sources); });
  const FolderClaim claim = claim_folder(cmd.out, {.kind = "sweep", .option = "--out",
                                                   .force = cmd.force},
                                         *Decomposition::world());
  const nlohmann::json summary = write_merged_sweep(
      sources, plan, cmd.out,
      {.figures = !cmd.no_plot, .diffuse = cmd.plot_diffuse, .page = !cmd.no_report});
  if (!cmd.quiet)
    std::cerr << fmt::format("merge: {} members of {} sweeps; wrote {}/sweep.csv{}\n",
                             summary.value("members", 0), sources.size(), cmd.out,
                             summary.contains("families_figure") ? ", families.png/.svg" : "");
  return 0;
}

}  // namespace

CommandFn add_merge_command(CLI::App& root) {
  auto cmd = std::make_shared<MergeCommand>();
  CLI::App* app = root.add_subcommand(
      "merge",
      "Sweeps computed apart (same run parameters) in one sweep folder: the members copied, "
      "one sweep.csv, sweep.json and families.png, as one sweep over every surface and "
      "volume fraction would have written them");
  app->add_option("sweeps", cmd->sources, "Complete sweep folders (two or more)")
      ->required()
      ->expected(2, -1)
      ->check(CLI::ExistingDirectory);
  app->add_option("--out", cmd->out, "The merged sweep's folder (new or empty)")
      ->required()
      ->check(non_empty_text(), "DIR");
  app->add_flag("--no-plot", cmd->no_plot, "Skip families.png");
  app->add_flag("--plot-diffuse", cmd->plot_diffuse,
                "families.png: also the diffuse layer's H and area (Appendix B)");
  app->add_flag("--no-report", cmd->no_report, "Skip report.html and gallery.png");
  add_force_option(*app, cmd->force);
  app->add_flag("--quiet", cmd->quiet, "No summary line");
  return {app, [cmd]() -> int { return merge(*cmd); }};
}

}  // namespace cmcsurf::cli
