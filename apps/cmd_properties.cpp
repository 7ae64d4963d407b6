// cmcsurf properties: effective stiffness and conductivities of a run's network or sheet solid
// (and of the nodal part peer tools print), from the field on its own grid (docs/properties.md).
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli_common.h"
#include "commands.h"
#include "io/json_file.h"
#include "io/png.h"
#include "mesh_options.h"
#include "pipeline/properties_pictures.h"
#include "pipeline/properties_stage.h"
#include "run_control.h"

namespace cmcsurf::cli {

namespace {

namespace fs = std::filesystem;

struct PropertiesCommand {
  std::string from;
  std::string solid = "network";
  int phase = 1;
  double porosity = NAN;
  double thickness = NAN;
  std::string material;  // E_GPa,nu
  bool compare_nodal = false;
  bool grid_check = false;
  std::string only = "elastic,conductivity,flow";
  double flow_rate = NAN;  // mL/min
  double flow_area = NAN;  // units^2
  double velocity = NAN;   // mm/s
  double viscosity = PropertiesRequest{}.viscosity_mpa_s;
  double tolerance = 1e-5;
  double cell_size = 1.0;
  std::string units = "cell";
  std::string out;
  int threads = 0;
  bool quiet = false;
};

PropertiesRequest request_of(const PropertiesCommand& cmd) {
  PropertiesRequest r;
  r.cell_size = cmd.cell_size;
  r.units = cmd.units;
  try {
    set_properties_solid(r, cmd.solid, cmd.phase, cmd.porosity, cmd.thickness);
    set_properties_only(r, cmd.only);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  try {
    set_properties_material(r, cmd.material);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  r.compare_nodal = cmd.compare_nodal;
  r.grid_check = cmd.grid_check;
  r.tolerance = cmd.tolerance;
  r.flow_rate_ml_min = cmd.flow_rate;
  r.flow_area = cmd.flow_area;
  r.velocity_mm_s = cmd.velocity;
  r.viscosity_mpa_s = cmd.viscosity;
  if (const std::string why = check_properties_request(r); !why.empty()) throw UsageError(why);
  return r;
}

std::string number(const nlohmann::json& j, const char* key, int index = -1) {
  if (!j.contains(key)) return "-";
  const nlohmann::json& v = index >= 0 ? j[key][std::size_t(index)] : j[key];
  return v.is_number() ? fmt::format("{:.4g}", v.get<double>()) : "-";
}

// The summary: the CMC part beside the nodal ones, one row per number.
void print_summary(const nlohmann::json& j) {
  std::vector<std::pair<std::string, const nlohmann::json*>> sides = {{"CMC", &j}};
  if (j.contains("nodal")) sides.push_back({"nodal", &j["nodal"]});
  if (j.contains("nodal_offset")) sides.push_back({"nodal offset", &j["nodal_offset"]});
  std::string head = fmt::format("{:<34}", "");
  for (const auto& s : sides) head += fmt::format("{:>14}", s.first);
  std::cerr << head << "\n";
  auto row = [&](const std::string& label, const char* key, int index, const char* sub = nullptr) {
    std::string line = fmt::format("{:<34}", label);
    for (const auto& s : sides) {
      const nlohmann::json& side =
          sub ? (*s.second).value(sub, nlohmann::json::object()) : *s.second;
      line += fmt::format("{:>14}", number(side, key, index));
    }
    std::cerr << line << "\n";
  };
  row("relative density", "relative_density", -1);
  if (j.contains("thickness")) row("sheet thickness (" + j.value("thickness_units", "") + ")",
                                  "thickness", -1);
  if (j.contains("stiffness_voigt")) {
    row("Young's modulus E_x / E_s", "youngs_modulus", 0);
    row("shear modulus G_yz / E_s", "shear_modulus", 0);
    row("Poisson ratio nu_xy", "poisson_ratio", 0);
    row("bulk modulus / E_s", "bulk_modulus", -1);
    row("Zener ratio", "zener_ratio", -1);
    row("E min / E_s", "youngs_modulus_min", -1);
    row("E max / E_s", "youngs_modulus_max", -1);
    row("bulk modulus / HS upper bound", "bulk_modulus", -1, "fraction_of_bound");
    if (j.contains("youngs_modulus_gpa")) row("Young's modulus E_x (GPa)", "youngs_modulus_gpa", 0);
  }
  if (j.contains("conductivity_solid")) {
    std::string line = fmt::format("{:<34}", "conductivity solid k_xx / k_s");
    for (const auto& s : sides)
      line += fmt::format(
          "{:>14}", fmt::format("{:.4g}", (*s.second)["conductivity_solid"][0][0].get<double>()));
    std::cerr << line << "\n";
    line = fmt::format("{:<34}", "conductivity pore k_xx / k_f");
    for (const auto& s : sides)
      line += fmt::format(
          "{:>14}", fmt::format("{:.4g}", (*s.second)["conductivity_pore"][0][0].get<double>()));
    std::cerr << line << "\n";
    row("pore tortuosity (x)", "tortuosity_pore", 0);
    row("k solid / HS upper bound", "conductivity_solid", -1, "fraction_of_bound");
  }
  if (j.contains("permeability")) {
    auto tensor_row = [&](const std::string& label, const char* key) {
      std::string line = fmt::format("{:<34}", label);
      for (const auto& s : sides) {
        const nlohmann::json& side = *s.second;
        const std::string v =
            side.contains(key) ? fmt::format("{:.4g}", side[key][0][0].get<double>()) : "-";
        line += fmt::format("{:>14}", v);
      }
      std::cerr << line << "\n";
    };
    tensor_row("permeability k_xx / cell^2", "permeability");
    if (j.contains("permeability_m2")) tensor_row("permeability k_xx (m^2)", "permeability_m2");
    row("hydraulic tortuosity (x)", "hydraulic_tortuosity", 0);
    row("specific surface (1/cell)", "specific_surface", -1);
    row("Kozeny-Carman constant", "kozeny_carman_constant", -1);
    row("wall shear median (z, mu U/L)", "median", -1, "wall_shear_stress");
    if (j.contains("wall_shear_stress_mpa")) {
      row("wall shear mean (z, mPa)", "mean", -1, "wall_shear_stress_mpa");
      row("wall shear p95 (z, mPa)", "p95", -1, "wall_shear_stress_mpa");
      row("pressure drop (z, Pa/m)", "pressure_drop_pa_per_m", -1);
    }
    if (j.contains("wall_shear_stress_axis_mean"))
      row("wall shear mean (axes, mu U/L)", "mean", -1, "wall_shear_stress_axis_mean");
    if (j.contains("wall_shear_stress_mpa_axis_mean"))
      row("wall shear mean (axes, mPa)", "mean", -1, "wall_shear_stress_mpa_axis_mean");
  }
  for (const auto& s : sides)
    for (const auto& w : (*s.second)["warnings"])
      std::cerr << fmt::format("warning ({}): {}\n", s.first, w.get<std::string>());
}

int properties(PropertiesCommand& cmd) {
  const PropertiesRequest base = request_of(cmd);
  const bool folder = fs::is_directory(cmd.from);
  if (cmd.out.empty() && !folder)
    throw UsageError("--out: required when --from is a field file (a run folder's default is "
                     "DIR/properties.json)");
  const fs::path out = cmd.out.empty() ? fs::path(cmd.from) / "properties.json" : fs::path(cmd.out);
  refuse_overwriting_inputs(field_inputs(cmd.from, "--from"), out);
  std::map<std::string, std::string> metadata;
  const Field phi = load_phi(cmd.from, "--from", &metadata);
  PropertiesRequest r = base;
  r.surface = metadata.count("surface") ? metadata["surface"] : "";
  if (const fs::path report = field_run_report(cmd.from); !report.empty() && fs::exists(report)) {
    const nlohmann::json j = read_json_file(report);
    if (j.contains("surface") && j["surface"].is_string()) r.surface = j["surface"];
  }
  // Writing into the run's own folder: one writer at a time (io/output_folder.h).
  FolderClaim claim;
  if (cmd.out.empty()) claim = claim_folder(cmd.from, {.kind = "run", .option = "--from"},
                                            *Decomposition::world());
  apply_threads(cmd.threads);
  nlohmann::json j;
  try {
    j = compute_properties(phi, r, [&](const std::string& line) {
      if (!cmd.quiet) std::cerr << line << "\n";
    });
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  j["source"] = cmd.from;
  if (!r.surface.empty()) j["surface"] = r.surface;
  j["version"] = version_string();
  // The directional Young's modulus beside the JSON (FILE-youngs.png), drawn before the writes.
  const PropertiesPicture picture = youngs_modulus_picture(
      j, fmt::format("{} {}, porosity {:.4f}", r.surface.empty() ? "field" : r.surface,
                     j.value("solid", std::string()), j.value("porosity", 0.0)));
  const fs::path picture_path = out.parent_path() / (out.stem().string() + "-youngs.png");
  if (!picture.image.rgb.empty()) {
    j["youngs_picture"] = picture_path.filename().string();
    j["youngs_picture_seconds"] = picture.seconds;
  }
  write_json_atomic(out, j);
  if (!picture.image.rgb.empty()) write_png(picture_path, picture.image);
  if (!cmd.quiet) {
    print_summary(j);
    std::cerr << fmt::format("properties in {:.1f} s; wrote {}{}\n",
                             j["properties_seconds"].get<double>(), out.string(),
                             picture.image.rgb.empty() ? "" : " and " + picture_path.string());
  }
  return 0;
}

}  // namespace

CommandFn add_properties_command(CLI::App& root) {
  auto cmd = std::make_shared<PropertiesCommand>();
  CLI::App* app = root.add_subcommand(
      "properties",
      "Effective stiffness (6x6, Young's, shear and bulk moduli, Poisson ratios, anisotropy) and "
      "conductivities (solid, pore space, tortuosity) of a run's network or sheet solid, beside "
      "the Hashin-Shtrikman bounds, by periodic voxel finite elements on the field's grid "
      "(docs/properties.md)\nExample: cmcsurf properties --from runs/gyroid --solid sheet "
      "--porosity 0.7 --material 110,0.34 --compare-nodal");
  app->add_option("--from", cmd->from, "Run folder (field.vti) or a .vti/.pvti file")->required();
  app->add_option("--solid", cmd->solid,
                  "network (one phase, its porosity the member's) or sheet (a wall around the "
                  "phi = 1/2 surface)")
      ->capture_default_str();
  app->add_option("--phase", cmd->phase, "Network: the solid phase, 1 (phi > 1/2) or 2")
      ->capture_default_str();
  app->add_option("--porosity", cmd->porosity, "Sheet: solve the wall thickness for this porosity");
  app->add_option("--thickness", cmd->thickness, "Sheet: wall thickness, in --units");
  app->add_option("--material", cmd->material,
                  "The solid's E_GPa,nu (nu alone defaults to 0.3): moduli also in GPa");
  app->add_flag("--compare-nodal", cmd->compare_nodal,
                "Also the nodal part at the same porosity as peer tools build it (network F > c; "
                "sheet |F| < c, and the constant-thickness offset of F = 0)");
  app->add_flag("--grid-check", cmd->grid_check,
                "Also solve on N/2 and give Richardson error estimates (*_error keys)");
  app->add_option("--only", cmd->only, "What to compute: elastic, conductivity, flow (a list)")
      ->capture_default_str();
  app->add_option("--flow-rate", cmd->flow_rate,
                  "Flow: mL/min through --flow-area (along z), for wall shear stress in mPa and "
                  "the pressure drop");
  app->add_option("--flow-area", cmd->flow_area, "Flow: the cross-section, in --units^2");
  app->add_option("--velocity", cmd->velocity,
                  "Flow: superficial (Darcy) velocity along z in mm/s, instead of --flow-rate");
  app->add_option("--viscosity", cmd->viscosity, "Flow: the fluid's viscosity, mPa s (water at "
                  "37 C)")
      ->capture_default_str();
  app->add_option("--tolerance", cmd->tolerance, "CG's relative residual")->capture_default_str();
  app->add_option("--cell-size", cmd->cell_size,
                  "Units per unit cell, for --thickness and permeability_m2")
      ->capture_default_str();
  app->add_option("--units", cmd->units, "Name of the length unit")->capture_default_str();
  app->add_option("--out", cmd->out, "FILE.json (default: DIR/properties.json)");
  add_threads_option(*app, cmd->threads);
  app->add_flag("--quiet", cmd->quiet, "No progress or summary");
  return {app, [cmd]() -> int { return properties(*cmd); }};
}

}  // namespace cmcsurf::cli
