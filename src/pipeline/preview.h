// The preview stage of a run (after the quality stage; docs/report.md): the relaxed phi = 1/2
// surface and the nodal twin {F = c} as drawable meshes with local mean curvature, one colour
// scale for both, and preview.png's picture. Its wall time is report.json's preview_seconds.
#pragma once

#include <string>

#include "grid/field.h"
#include "measure/quality.h"
#include "pipeline/cmc.h"
#include "render/draw_surface.h"
#include "render/image.h"
#include "render/preview.h"

namespace cmcsurf {

// Lattice cells per side (at most) of the drawn meshes: preview.png and a sweep's gallery.png,
// a run's report.html, each member of a sweep's report.html.
inline constexpr int kPreviewCells = 64;
inline constexpr int kPageCells = 48;  // the meshes inlined in a run's report.html
inline constexpr int kSweepMemberCells = 32;

struct PreviewSurfaces {
  DrawSurface relaxed;
  bool has_nodal = false;
  DrawSurface nodal;
  // Centred on the run's mean curvature; reaching the 95th area percentile of |H - centre|
  // over both surfaces (at least 1e-3 max(1, |H|)).
  ColorScale scale;
};

// psi: tanh_profile_inverse of the whole final field (measure/sharp_surface.h; ghost 2, halo
// current). nodal_level: c of the nodal surface {F + 1/2 = c} (CmcQuality::nodal_level), used
// when `surface` is nodal. The relaxed surface's H comes from psi's full resolution; the nodal
// formula is sampled on the drawing lattice. On a block of a decomposed psi every process calls
// it (and make_run_preview) and rank 0 gets the surfaces (and the picture); the others get empty
// ones.
PreviewSurfaces preview_surfaces(const Field& psi, const std::string& surface, double nodal_level,
                                 double mean_curvature, int max_cells, bool with_nodal = true);
// psi = atanh(2 phi - 1) of a field (its block), ghost 2, for preview_surfaces.
Field profile_inverse(const Field& phi);

struct RunPreview {
  PreviewSurfaces surfaces;
  Image image;  // preview.png
  double seconds = 0.0;
};

// The stage: surfaces at kPreviewCells and the picture with its title (surface, alpha, H).
// psi: profile_inverse of the final field.
RunPreview make_run_preview(const Field& psi, const RunParams& p, const RunResult& r,
                            const CmcQuality& q);

// Title and labels of preview.png from the report's values.
PreviewLabels preview_labels(const std::string& surface, double alpha, double mean_curvature,
                             int grid, double epsilon, double relaxed_std, double nodal_std,
                             bool has_nodal);

// A sweep member's unit cell for gallery.png (the relaxed surface of its preview stage).
struct GalleryMember {
  std::string surface;
  std::string name;
  double alpha = 0.0;
  double mean_curvature = 0.0;
  DrawSurface relaxed;
};

}  // namespace cmcsurf
