#include "properties_options.h"

#include <cmath>
#include <stdexcept>

#include "cli_common.h"

namespace cmcsurf::cli {

void add_properties_options(CLI::App& app, PropertiesStage& stage, const std::string& what) {
  app.add_flag("--properties", stage.enabled,
               "Also the effective stiffness and conductivities of " + what +
                   " solid (phase 1's network unless --properties-solid) into report.json "
                   "(properties, properties_*; docs/properties.md)");
  app.add_option("--properties-solid", stage.solid,
                 "--properties of this solid: network (phase 1) or sheet (a wall around the "
                 "surface, with --properties-porosity or --properties-thickness)")
      ->check(non_empty_text(), "network|sheet");
  app.add_option("--properties-porosity", stage.porosity,
                 "--properties-solid sheet: the wall's porosity (0 < P < 1)");
  app.add_option("--properties-thickness", stage.thickness,
                 "--properties-solid sheet: the wall's thickness in unit cells (0 < T < 0.5); "
                 "a sweep's members then differ in density");
  app.add_flag("--properties-nodal", stage.nodal,
               "--properties with the nodal part at the same porosity beside it "
               "(properties.nodal, properties_nodal_*; a sheet: also properties.nodal_offset)");
  app.add_flag("--properties-grid-check", stage.grid_check,
               "--properties with the same on N/2 and Richardson errors (properties_*_error; "
               "a sweep chart's error bars); even N >= 16");
}

void finish_properties_options(PropertiesStage& stage, const std::string& surface, int grid) {
  if (stage.solid != "network" || !std::isnan(stage.porosity) || !std::isnan(stage.thickness) ||
      stage.nodal || stage.grid_check)
    stage.enabled = true;
  if (!stage.enabled) return;
  try {
    stage_properties_request(stage, surface, grid);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
}

void add_properties_outputs(nlohmann::json& outputs, const PropertiesStage& stage) {
  outputs["properties"] = stage.enabled;
  outputs["properties_solid"] = stage.solid;
  if (!std::isnan(stage.porosity)) outputs["properties_porosity"] = stage.porosity;
  if (!std::isnan(stage.thickness)) outputs["properties_thickness"] = stage.thickness;
  outputs["properties_nodal"] = stage.nodal;
  outputs["properties_grid_check"] = stage.grid_check;
}

void restore_properties_outputs(const OutputRestorer& r, PropertiesStage& stage) {
  r.restore("--properties", "properties", stage.enabled);
  r.restore("--properties-solid", "properties_solid", stage.solid);
  r.restore("--properties-porosity", "properties_porosity", stage.porosity);
  r.restore("--properties-thickness", "properties_thickness", stage.thickness);
  r.restore("--properties-nodal", "properties_nodal", stage.nodal);
  r.restore("--properties-grid-check", "properties_grid_check", stage.grid_check);
}

}  // namespace cmcsurf::cli
