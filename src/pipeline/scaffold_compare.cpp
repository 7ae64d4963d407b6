#include "pipeline/scaffold_compare.h"

#include <chrono>
#include <stdexcept>

#include "common/wall_clock.h"
#include "pipeline/sweep.h"
#include "surfaces/nodal_level.h"

namespace cmcsurf {

namespace {

nlohmann::json side(const nlohmann::json& report, const CurvatureDistribution& h,
                    double cell_size) {
  const auto& m = report["morphometry"];
  nlohmann::json j = {{"porosity", report["porosity"]},
                      {"specific_surface", m["specific_surface"]},
                      {"mean_curvature", h.mean / cell_size},
                      {"mean_curvature_std", h.std / cell_size},
                      {"triangles", report["triangles"]}};
  for (const char* key : {"wall_thickness", "pore_size"})
    if (m.contains(key))
      j[key] = {{"mean", m[key]["mean"]}, {"std", m[key]["std"]}, {"min", m[key]["min"]},
                {"max", m[key]["max"]}, {"p5", m[key]["p5"]}, {"p50", m[key]["p50"]},
                {"p95", m[key]["p95"]}};
  if (m.contains("throat")) j["throat"] = m["throat"]["min"];
  if (report.contains("sheet")) j["thickness"] = report["sheet"]["thickness"];
  return j;
}

}  // namespace

nlohmann::json compare_with_nodal(const Field& phi, const RunParams& params,
                                  const ScaffoldDesign& d, const ScaffoldPart& cmc,
                                  const ShapeFill* shape) {
  const auto t0 = std::chrono::steady_clock::now();
  const CmcQuality q = measure_cmc_quality(phi, params);
  if (!q.has_nodal)
    throw std::invalid_argument("--compare-nodal: the surface has no nodal approximation");
  // The twin as a phase field: f - c + 1/2, so that its 1/2 level is the nodal surface {F = c}.
  const NodalLevelSet nodal = nodal_level_set(params.surface, params.volume_fraction, params.grid);
  Field twin = nodal_level_function(nodal);
  for_each_cell(twin.n(), [&](int i, int j, int k) { twin(i, j, k) += 0.5; });
  twin.exchange_halo();
  const double units = d.cell_size;
  nlohmann::json nodal_side;
  try {
    nodal_side = side(design_scaffold(twin, d, shape).report, q.nodal, units);
  } catch (const ClosedCellError& e) {
    nodal_side = {{"error", e.what()}};  // the twin may close pores the CMC part keeps open
  }
  return {{"cmc", side(cmc.report, q.relaxed, units)},
          {"nodal", nodal_side},
          {"nodal_level", nodal.level},
          {"shape", shape != nullptr},
          {"note",
           "the same design (box or --shape) from the nodal approximation at the "
           "member's volume fraction (surfaces/nodal_level.h); mean curvature and its "
           "area-weighted spread in "
           "1/" +
               d.units + ", sharp estimators (docs/families.md)"},
          {"seconds", seconds_since(t0)}};
}

}  // namespace cmcsurf
