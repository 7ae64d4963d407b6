// The pages of a run or sweep folder (docs/report.md): report.html, made from the folder's
// files alone (report.json, history.csv, curvature_histogram.csv, field.vti; for a sweep also
// sweep.json, sweep.csv, families.png and each member's folder), so `cmcsurf report DIR`
// remakes it at any time; and a sweep's gallery.png. The CLI (run, sweep, report) and the
// Python module (Result.save) call these.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/preview.h"
#include "render/draw_surface.h"

namespace cmcsurf {

// Writes dir/report.html for a run folder; returns its wall time in seconds. Throws
// std::runtime_error naming the file that is missing or unreadable. `surfaces`: the page's
// meshes (kPageCells) when the caller computed them (run_outputs); otherwise they are drawn
// from the folder's field.vti. `report`: the run's report.json when the caller has it and has
// not written it yet (a run writes report.json last, after this page), else it is read.
double write_run_page(const std::filesystem::path& dir, const PreviewSurfaces* surfaces = nullptr,
                      const nlohmann::json* report = nullptr);
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
