// The page of a printed part (docs/scaffolds.md, "The part's page"): FILE.html and a FILE.png
// preview beside `cmcsurf scaffold`'s FILE. What costs time (the part decimated for the
// browser, the slices) is measure_part_page, whose seconds go into FILE.json; the writer only
// formats it with FILE.json's numbers. `cmcsurf report FILE.json` reads the part back and
// remakes both.
#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mesh/tri_mesh.h"
#include "render/draw_surface.h"

namespace cmcsurf {

// Triangles of the part the browser draws (about 4 MB of page).
inline constexpr std::size_t kPartPageTriangles = 150000;

struct PartSlice {
  int axis = 2;                          // the plane x[axis] = at
  double at = 0.0;                       // output units
  std::array<int, 2> plane_axes{0, 1};   // the slice's horizontal and vertical axes
  std::array<double, 2> lo{}, hi{};      // the part's extent along them
  std::vector<std::array<double, 4>> segments;  // the surface's trace: x0 y0 x1 y1
};

struct PartPageMeasures {
  // The part in the unit cube (scaled by its longest extent, centred), coloured by height.
  DrawSurface view;
  std::size_t view_triangles = 0, part_triangles = 0;
  std::vector<PartSlice> slices;  // z and x at 0.4 of the box (off the lattice's mirror planes)
  double view_seconds = 0.0, slice_seconds = 0.0;
};

PartPageMeasures measure_part_page(const TriMesh& part,
                                   std::size_t max_triangles = kPartPageTriangles);

// FILE.json's seconds of the page's stages (page_view, page_slices).
nlohmann::json part_page_seconds(const PartPageMeasures& m);

// Writes html (the page) and png (the preview) from FILE.json's report and the measures.
// Returns the wall time.
double write_part_page(const std::filesystem::path& html, const std::filesystem::path& png,
                       const nlohmann::json& report, const PartPageMeasures& m);

// A graded part's sections of the page (empty for an ungraded one): the porosity profile,
// target against measured along the axis or by depth (`graded.profile`, or
// `graded_cell_size.profile`), drawn and tabled, and the wall and pore of the cells it blends
// (`morphometry.members`). Every number cell names its JSON pointer into the report.
std::string graded_profile_html(const nlohmann::json& report);

// FILE.json -> FILE (its part: 3MF or STL), measured and written as FILE.html, FILE.png.
// Throws std::runtime_error naming what is missing or unreadable. Returns the wall time.
double write_part_page_from_report(const std::filesystem::path& report_json);

// FILE.html and FILE.png for a part FILE.
std::filesystem::path part_page_path(const std::filesystem::path& part);
std::filesystem::path part_preview_path(const std::filesystem::path& part);

}  // namespace cmcsurf
