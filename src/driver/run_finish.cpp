#include "driver/run_finish.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>

#include "common/wall_clock.h"
#include "io/checkpoint.h"
#include "io/mesh_output.h"
#include "io/png.h"
#include "io/run_folder.h"
#include "io/run_report.h"
#include "pipeline/distributed_mesh.h"
#include "pipeline/properties_pictures.h"
#include "report/run_page.h"
#include "surfaces/initial.h"

namespace cmcsurf {

nlohmann::json properties_outputs_json(const PropertiesStage& stage, const std::string& porosity) {
  nlohmann::json outputs = {{"properties", stage.enabled},
                            {"properties_solid", stage.solid},
                            {"properties_nodal", stage.nodal},
                            {"properties_grid_check", stage.grid_check}};
  if (!porosity.empty()) outputs["properties_porosity"] = porosity;
  if (!std::isnan(stage.thickness)) outputs["properties_thickness"] = stage.thickness;
  return outputs;
}

FinishedRun finish_run_folder(const std::filesystem::path& dir, const RunParams& p,
                              const RunResult& r, RunOutputs& outputs,
                              const RunFolderOptions& o,
                              nlohmann::json extra) {
  const Decomposition* group = r.phi.decomposition();
  const bool distributed = group != nullptr && group->distributed();
  FinishedRun out;
  out.writer = !distributed || group->rank() == 0;
  if (outputs.preview) extra["preview_seconds"] = outputs.preview->seconds;
  if (outputs.page) extra["page_seconds"] = outputs.page_seconds;
  PropertiesPicture youngs;  // youngs_modulus.png, drawn before the writes
  if (o.properties.enabled) {  // the stage's solid (docs/properties.md)
    extra.update(run_properties_keys(r.phi, p.surface, o.properties));
    if (out.writer && o.pictures) {
      youngs = youngs_modulus_picture(extra["properties"],
                                      properties_title(p.surface, extra["properties"]));
      if (!youngs.image.rgb.empty()) extra["youngs_picture_seconds"] = youngs.seconds;
    }
  }
  // --mesh: the surface mesh, computed before the writes (rank 0 gets it under MPI).
  std::optional<Scaffold> surface;
  if (!o.mesh_format.empty()) {
    const auto t0 = std::chrono::steady_clock::now();
    surface = distributed_surface_scaffold(r.phi, ScaffoldParams{});
    extra["surface_mesh_seconds"] = seconds_since(t0);
  }
  double field_seconds = 0.0;
  if (distributed)  // field.pvti: one piece per process
    field_seconds =
        write_run_field_pieces(dir, p, r, outputs.quality, o.threads, o.float32, extra);
  if (o.layout != nullptr) {
    if (o.layout->distributed()) {
      // Every process's peak resident memory (the report's peak_memory_bytes is rank 0's).
      const std::vector<std::uint64_t> peaks = allgather_world({peak_memory_bytes()});
      extra["peak_memory_bytes_per_rank"] = peaks;
      extra["peak_memory_bytes_max_rank"] = *std::max_element(peaks.begin(), peaks.end());
    }
    extra.update(decomposition_json(*o.layout));  // after the last collective
  }
  if (!out.writer) return out;
  const RunFieldSource field = distributed ? RunFieldSource(FieldPiecesWritten{field_seconds})
                                           : RunFieldSource(std::cref(r.phi));
  out.report = write_run_folder(
      dir, p, r, field, outputs.quality, o.threads, o.float32, extra,
      [&](const nlohmann::json& report_to_be) {
        if (surface) write_run_surface_mesh(dir, *surface, o.mesh_format);
        if (outputs.preview) write_png(dir / "preview.png", outputs.preview->image);
        if (!youngs.image.rgb.empty()) write_png(dir / kYoungsPictureName, youngs.image);
        if (outputs.page)
          write_run_page(dir, *outputs.page,
                         {report_to_be, history_csv(r.history),
                          curvature_histogram_csv(outputs.quality)});
      });
  if (o.remove_checkpoint) remove_checkpoint(dir / kCheckpointFileName);
  return out;
}

RunOutputs run_pictures(const RunParams& p, const RunResult& r, const CmcQuality& quality,
                        bool preview, bool page) {
  RunOutputs out;
  out.quality = quality;
  if (!preview && !page) return out;
  const Field psi = profile_inverse(r.phi);
  if (preview) out.preview = make_run_preview(psi, p, r, quality);
  if (page) {
    const auto t0 = std::chrono::steady_clock::now();
    out.page = preview_surfaces(psi, p.surface, quality.nodal_level, r.final.mean_curvature,
                                kPageCells, quality.has_nodal);
    out.page_seconds = seconds_since(t0);
  }
  return out;
}

}  // namespace cmcsurf
