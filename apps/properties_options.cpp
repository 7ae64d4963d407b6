#include "properties_options.h"

#include <cmath>
#include <stdexcept>

#include "cli_common.h"
#include "driver/run_finish.h"

namespace cmcsurf::cli {

void add_properties_options(CLI::App& app, PropertiesOptions& options, const std::string& what) {
  PropertiesStage& stage = options.stage;
  app.add_flag("--properties", stage.enabled,
               "Also the effective stiffness and conductivities of " + what +
                   " solid (phase 1's network unless --properties-solid) into report.json "
                   "(properties, properties_*; docs/properties.md)");
  app.add_option("--properties-solid", stage.solid,
                 "--properties of this solid: network (phase 1) or sheet (a wall around the "
                 "surface, with --properties-porosity or --properties-thickness)")
      ->check(non_empty_text(), "network|sheet");
  app.add_option("--properties-porosity", options.porosity,
                 "--properties-solid sheet: the wall's porosity (0 < P < 1), or a ramp "
                 "P1,P2,... (properties_ramp; one chart point per porosity)")
      ->check(non_empty_text(), "P[,P2,...]");
  app.add_option("--properties-thickness", stage.thickness,
                 "--properties-solid sheet: the wall's thickness in unit cells (0 < T < 0.5)");
  app.add_flag("--properties-nodal", stage.nodal,
               "--properties with the nodal part at the same porosity beside it "
               "(properties.nodal, properties_nodal_*; a sheet: also properties.nodal_offset)");
  app.add_flag("--properties-grid-check", stage.grid_check,
               "--properties with the same on N/2 and Richardson errors (properties_*_error; "
               "a sweep chart's error bars); even N >= 16");
}

void finish_properties_options(PropertiesOptions& options, const std::string& surface,
                               int grid) {
  PropertiesStage& stage = options.stage;
  try {
    stage.porosities = parse_properties_porosities(options.porosity);
    if (stage.solid != "network" || !stage.porosities.empty() || !std::isnan(stage.thickness) ||
        stage.nodal || stage.grid_check)
      stage.enabled = true;
    if (stage.enabled) stage_properties_request(stage, surface, grid);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
}

void add_properties_outputs(nlohmann::json& outputs, const PropertiesOptions& options) {
  outputs.update(properties_outputs_json(options.stage, options.porosity));
}

void restore_properties_outputs(const OutputRestorer& r, PropertiesOptions& options) {
  PropertiesStage& stage = options.stage;
  r.restore("--properties", "properties", stage.enabled);
  r.restore("--properties-solid", "properties_solid", stage.solid);
  r.restore("--properties-porosity", "properties_porosity", options.porosity);
  r.restore("--properties-thickness", "properties_thickness", stage.thickness);
  r.restore("--properties-nodal", "properties_nodal", stage.nodal);
  r.restore("--properties-grid-check", "properties_grid_check", stage.grid_check);
}

}  // namespace cmcsurf::cli
