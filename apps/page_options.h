// --no-preview and --no-report of run and sweep (docs/report.md); the pages themselves are
// written by the library (report/run_page.h).
#pragma once

#include <CLI/CLI.hpp>

namespace cmcsurf::cli {

struct PageOptions {
  bool no_preview = false;  // run, sweep: no preview.png (and no gallery.png)
  bool no_report = false;   // run, sweep: no report.html at the end
};
void add_page_options(CLI::App& app, PageOptions& options);

}  // namespace cmcsurf::cli
