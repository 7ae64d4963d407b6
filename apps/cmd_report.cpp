// cmcsurf report DIR: (re)writes DIR/report.html from a run or sweep folder (docs/report.md).
#include <fmt/format.h>

#include <filesystem>
#include <iostream>

#include "cli_common.h"
#include "commands.h"
#include "report/part_page.h"
#include "report/run_page.h"
#include "run_control.h"

namespace cmcsurf::cli {

namespace {

namespace fs = std::filesystem;

struct ReportCommand {
  std::string dir;
  bool quiet = false;
};

// A part's FILE.json (cmcsurf scaffold): FILE.html and FILE.png from it and FILE.
int part_report(const ReportCommand& cmd) {
  double seconds = 0.0;
  try {
    seconds = write_part_page_from_report(cmd.dir);
  } catch (const std::runtime_error& e) {
    throw UsageError(fmt::format("FILE.json: {}", e.what()));
  }
  const std::string part = cmd.dir.substr(0, cmd.dir.size() - 5);
  if (!cmd.quiet)
    std::cerr << fmt::format("wrote {} and {} in {:.2f} s\n", part_page_path(part).string(),
                             part_preview_path(part).string(), seconds);
  return 0;
}

int report(const ReportCommand& cmd) {
  const fs::path dir(cmd.dir);
  if (fs::is_regular_file(dir) && dir.extension() == ".json") return part_report(cmd);
  if (!fs::is_directory(dir))
    throw UsageError(fmt::format(
        "DIR: '{}' is not a directory; accepted: a run folder (with report.json), a sweep "
        "folder (with sweep.json) or a part's FILE.json (cmcsurf scaffold)",
        cmd.dir));
  const bool sweep = fs::exists(dir / "sweep.json");
  if (!sweep && !fs::exists(dir / "report.json"))
    throw UsageError(fmt::format(
        "DIR: '{}' has neither report.json (a run folder) nor sweep.json (a sweep folder); "
        "a run or sweep writes these last, so the run may have stopped before it finished",
        cmd.dir));
  // Written by cmcsurf, and not being written now (io/output_folder.h).
  const FolderClaim claim = claim_folder(dir, {.kind = sweep ? "sweep" : "run", .option = "DIR"},
                                         *Decomposition::world());
  // A sweep's gallery.png (missing after --no-preview, or an interrupted sweep) from its
  // members' folders, since the page shows it.
  if (sweep && !fs::exists(dir / "gallery.png")) {
    const double gallery = write_gallery_from_folder(dir);
    if (!cmd.quiet)
      std::cerr << fmt::format("wrote {} in {:.2f} s\n", (dir / "gallery.png").string(), gallery);
  }
  const double seconds = sweep ? write_sweep_page(dir) : write_run_page(dir);
  if (!cmd.quiet)
    std::cerr << fmt::format("wrote {} in {:.2f} s\n", (dir / "report.html").string(), seconds);
  return 0;
}

}  // namespace

CommandFn add_report_command(CLI::App& root) {
  auto cmd = std::make_shared<ReportCommand>();
  CLI::App* app = root.add_subcommand(
      "report",
      "Write DIR/report.html: one self-contained page (3D view, convergence, curvature "
      "histogram, key numbers) from a run or sweep folder; run and sweep write it themselves "
      "unless --no-report. Given a part's FILE.json (cmcsurf scaffold), (re)writes FILE.html "
      "and FILE.png");
  app->add_option("DIR", cmd->dir,
                  "A run folder (report.json), a sweep folder (sweep.json) or a part's FILE.json")
      ->required();
  app->add_flag("--quiet", cmd->quiet, "No output");
  return {app, [cmd]() -> int { return report(*cmd); }};
}

}  // namespace cmcsurf::cli
