// The pages of a run or sweep folder (docs/report.md): report.html, which can be made from the
// folder's files alone (report.json, history.csv, curvature_histogram.csv, field.vti; for a
// sweep also sweep.json, sweep.csv, families.png and each member's folder), so `cmcsurf report
// DIR` remakes it at any time (a finishing run hands its own data instead); and a sweep's
// gallery.png. The CLI (run, sweep, report) and the
// Python module (Result.save) call these.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/preview.h"
#include "render/draw_surface.h"

namespace cmcsurf {

// Writes dir/report.html for a run folder from its files (report.json, history.csv,
// curvature_histogram.csv); returns its wall time in seconds. Throws std::runtime_error naming
// the file that is missing or unreadable. `surfaces`: the page's meshes (kPageCells) when the
// caller computed them; otherwise they are drawn from the folder's field.vti.
double write_run_page(const std::filesystem::path& dir, const PreviewSurfaces* surfaces = nullptr);

// What a finishing run hands its page instead of the files: the report to be written (a run
// writes report.json last, after this page) and the text of history.csv and
// curvature_histogram.csv (history_csv, curvature_histogram_csv: io/run_report.h).
struct RunPageData {
  nlohmann::json report;
  std::string history_csv;
  std::string curvature_histogram_csv;
};
// The same page from the run's own data and meshes (run_outputs), byte for byte what the
// folder's files give (tests/cli/report_page.sh compares), with no file read but the folder's
// pictures (youngs_modulus.png).
double write_run_page(const std::filesystem::path& dir, const PreviewSurfaces& surfaces,
                      const RunPageData& data);
// Writes dir/report.html for a sweep folder (sweep.json beside the member folders).
double write_sweep_page(const std::filesystem::path& dir);

// Draws dir/gallery.png: one row per family, members in sweep order, on one colour scale
// centred on H = 0, beside dir/families.png if it exists. Returns the stage's wall time.
double write_gallery(const std::filesystem::path& dir, const std::vector<GalleryMember>& members);
// A member's tile from its folder alone (report.json, field.vti): the tile the sweep drew when
// it computed the member (the same surface from a Float64 field), for members an earlier
// invocation computed (sweep --resume).
GalleryMember gallery_member_from_folder(const std::filesystem::path& member_dir,
                                         const std::string& surface, const std::string& name,
                                         double alpha);
// gallery.png of every member sweep.json lists, from their folders (cmcsurf report on a sweep
// without one). Returns the wall time.
double write_gallery_from_folder(const std::filesystem::path& dir);

}  // namespace cmcsurf
