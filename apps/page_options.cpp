#include "page_options.h"

namespace cmcsurf::cli {

void add_page_options(CLI::App& app, PageOptions& options) {
  app.add_flag("--no-preview", options.no_preview,
               "Do not draw preview.png nor --properties' youngs_modulus.png (sweep: nor "
               "gallery.png)");
  app.add_flag("--no-report", options.no_report,
               "Do not write report.html (`cmcsurf report DIR` writes it later)");
}

}  // namespace cmcsurf::cli
