#include "pipeline/preview.h"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "common/wall_clock.h"
#include "measure/sharp_surface.h"
#include "parallel/first_exception.h"
#include "surfaces/initial.h"
#include "surfaces/nodal_level.h"

namespace cmcsurf {

Field profile_inverse(const Field& phi) {
  Field psi = Field::like(phi, 2);
  tanh_profile_inverse(phi, psi);
  return psi;
}

PreviewSurfaces preview_surfaces(const Field& psi, const std::string& surface, double nodal_level,
                                 double mean_curvature, int max_cells, bool with_nodal) {
  PreviewSurfaces out;
  const Decomposition* d = psi.decomposition();
  const bool nodal = with_nodal && is_nodal_surface(surface);
  // The nodal surface, its spread: rank 0 alone.
  double nodal_spread = 0.0;
  const auto draw_nodal = [&] {
    // F is a trigonometric polynomial: sampled on the drawing lattice itself its curvature is
    // already good to O(h^2) there, and at 256^3 that saves 63 of every 64 evaluations.
    InitialFieldParams init;
    init.surface = surface;
    NodalLevelSet level_set;
    level_set.f = make_initial_field(init, psi.n() / draw_stride(psi.n(), max_cells), 2);
    level_set.level = nodal_level;
    out.nodal = draw_surface(nodal_level_function(level_set), max_cells);
    out.has_nodal = true;
    nodal_spread = curvature_spread(out.nodal, mean_curvature, 0.95);
  };
  double spread = 0.0;
  if (d && d->distributed()) {
    out.relaxed = draw_surface(psi, max_cells);  // collective
    if (d->rank() != 0) return out;  // rank 0 draws (the rest is small)
    spread = curvature_spread(out.relaxed, mean_curvature, 0.95);
    if (nodal) draw_nodal();
  } else {
    // The two surfaces are independent (each a serial extraction and a sort): one a thread.
    FirstException errors;
#pragma omp parallel for schedule(static, 1) num_threads(2) if (nodal && omp_get_max_threads() > 1)
    for (int task = 0; task < 2; ++task)
      errors.run([&] {
        if (task == 0) {
          out.relaxed = draw_surface(psi, max_cells);
          spread = curvature_spread(out.relaxed, mean_curvature, 0.95);
        } else if (nodal) {
          draw_nodal();
        }
      });
    errors.rethrow();
  }
  spread = std::max(spread, nodal_spread);
  out.scale.centre = mean_curvature;
  out.scale.half_range = std::max(spread, 1e-3 * std::max(1.0, std::abs(mean_curvature)));
  return out;
}

PreviewLabels preview_labels(const std::string& surface, double alpha, double mean_curvature,
                             int grid, double epsilon, double relaxed_std, double nodal_std,
                             bool has_nodal) {
  std::string name = surface;
  if (name.size() > 36) name = name.substr(0, 33) + "...";
  PreviewLabels l;
  l.title = fmt::format("{}    α = {:.4g}    H = {:+.5g}", name, alpha, mean_curvature);
  l.subtitle = fmt::format("{}³ cells, ε = {:.3g}; colour: local mean curvature of φ = 1/2", grid,
                           epsilon);
  l.relaxed = fmt::format("{}: H std {:.3g}", has_nodal ? "relaxed (CMC)" : "relaxed", relaxed_std);
  if (has_nodal) l.nodal = fmt::format("nodal, same volume: H std {:.3g}", nodal_std);
  return l;
}

RunPreview make_run_preview(const Field& psi, const RunParams& p, const RunResult& r,
                            const CmcQuality& q) {
  const auto t0 = std::chrono::steady_clock::now();
  RunPreview out;
  const double h = r.final.mean_curvature;
  out.surfaces = preview_surfaces(psi, p.surface, q.nodal_level, h, kPreviewCells, q.has_nodal);
  if (psi.decomposition() && psi.decomposition()->rank() != 0) return out;
  const double alpha = is_nodal_surface(p.surface) ? p.volume_fraction : r.final.volume_fraction;
  const PreviewLabels labels = preview_labels(p.surface, alpha, h, p.grid, p.epsilon,
                                              q.relaxed.std, q.nodal.std, out.surfaces.has_nodal);
  out.image = render_preview(out.surfaces.relaxed,
                             out.surfaces.has_nodal ? &out.surfaces.nodal : nullptr,
                             out.surfaces.scale, labels);
  out.seconds = seconds_since(t0);
  return out;
}

}  // namespace cmcsurf
