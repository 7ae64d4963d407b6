// What a solid does (docs/properties.md): its effective stiffness and conductivities from the
// voxel homogenisation of properties/, as the dictionary `cmcsurf properties` writes to
// FILE.json, `run --properties` adds to report.json and Python returns. One place computes and
// names every number; the command line and the module only translate options.
#pragma once

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "grid/field.h"
#include "properties/voxel_solid.h"

namespace cmcsurf {

struct PropertiesRequest {
  SolidSpec solid;                  // network or sheet, phase, thickness or porosity
  double youngs_modulus_gpa = NAN;  // E_s of the material (--material E_GPa,nu); NaN: none
  double poisson_ratio = 0.3;       // nu_s
  bool elastic = true;              // --only elastic,conductivity
  bool conductivity = true;
  bool flow = true;                 // Stokes flow through the pores (--only ...,flow)
  // Flow for the wall shear stress and pressure drop (along z): a volumetric flow rate in
  // mL/min through a cross-section of flow_area (--units^2), or a superficial (Darcy) mean
  // velocity in mm/s; the fluid's viscosity in mPa s (water at 37 C: 0.692).
  double flow_rate_ml_min = NAN;
  double flow_area = NAN;
  double velocity_mm_s = NAN;
  double viscosity_mpa_s = 0.692;
  bool compare_nodal = false;       // the nodal twin(s) at the same porosity
  bool grid_check = false;          // N and N/2, Richardson, *_error
  double tolerance = 1e-5;          // CG's relative residual
  std::string surface;              // the nodal formula of the member (for compare_nodal)
  double cell_size = 1.0;           // output units per unit cell (thickness in these units)
  std::string units = "cell";
};

// The solid and what to compute as the user names them (--solid network|sheet, --phase 1|2,
// --porosity or --thickness, NaN where not given; --only elastic,conductivity): the request's
// fields, or std::invalid_argument naming the option and what is accepted.
void set_properties_solid(PropertiesRequest& r, const std::string& solid, long long phase,
                          double porosity, double thickness);
void set_properties_only(PropertiesRequest& r, const std::string& only);
// --material E_GPa[,nu] (nu 0.3 when left out; "" leaves the request as it is): the request's
// youngs_modulus_gpa and poisson_ratio, or std::invalid_argument naming --material and the
// accepted form (the ranges are check_properties_request's).
void set_properties_material(PropertiesRequest& r, const std::string& material);

// Metres per unit of --units ("um", "mm", "cm", "m", "in"); NaN for "cell" or unknown.
double metres_per_unit(const std::string& units);

// Why the request cannot be computed ("" if it can), naming the option: ranges of
// --material, --tolerance, --porosity/--thickness, --only, --flow-rate/--flow-area/--velocity,
// --viscosity.
std::string check_properties_request(const PropertiesRequest& r);

// The properties of the CMC field's solid (and, with compare_nodal, the nodal part as peer
// tools build it, in "nodal", and for a sheet the constant-thickness offset in
// "nodal_offset"). phi: a whole grid, ghost >= 2. `progress` gets a line per stage (may be
// empty). Throws std::invalid_argument for a request out of range or a field with no surface.
nlohmann::json compute_properties(const Field& phi, const PropertiesRequest& r,
                                  const std::function<void(const std::string&)>& progress = {});

// The scalars of a properties dictionary for report.json's top level and sweep.csv's columns:
// properties_relative_density, properties_youngs_modulus (mean over x, y, z), ..._shear_modulus,
// ..._poisson_ratio, ..._bulk_modulus, ..._zener_ratio, ..._conductivity_solid and
// ..._conductivity_pore (mean diagonals), ..._tortuosity_pore (mean), ..._permeability (mean
// diagonal, cell-size^2), ..._hydraulic_tortuosity (mean), with their *_error when
// grid-checked, ..._specific_surface (per cell size), ..._kozeny_carman_constant and
// ..._wall_shear_stress (mean over the walls and the axes, mu U / L) with flow, and the same of
// the nodal twin as properties_nodal_*.
nlohmann::json properties_summary(const nlohmann::json& properties);

// The --properties stage of `run` and `sweep` (and Python's run/sweep) as the user asks for it;
// the options --properties-solid, --properties-porosity, --properties-thickness,
// --properties-nodal and --properties-grid-check.
struct PropertiesStage {
  bool enabled = false;           // --properties (any other --properties-* implies it)
  std::string solid = "network";  // network (phase 1) or sheet
  // sheet: one of porosities and thickness (unit cells; NaN: none). Several porosities are a
  // ramp: the sheet at each, "properties" the first's, "properties_ramp" all of them.
  std::vector<double> porosities;
  double thickness = NAN;
  bool nodal = false;       // the nodal twin(s) at the same porosity
  bool grid_check = false;  // N and N/2: *_error, the chart's error bars
};

// --properties-porosity's text: P or a ramp P1,P2,... (at most 16), or std::invalid_argument
// naming the option. "" is none.
std::vector<double> parse_properties_porosities(const std::string& text);

// The request of a stage (at its first porosity) for a member of `surface` on `grid`^3, or
// std::invalid_argument naming the stage's option (--properties-solid, ...) and what it accepts.
PropertiesRequest stage_properties_request(const PropertiesStage& stage,
                                           const std::string& surface, int grid);

// The report.json keys of the --properties stage of `run` and `sweep`: the stage's solid of a
// run's field (and its nodal twins with `nodal`) as "properties", its summary scalars and
// "properties_seconds"; with a ramp of porosities also "properties_ramp", per porosity the
// summary scalars and "properties_porosity" (what the designer's chart draws for the member).
nlohmann::json run_properties_keys(const Field& phi, const std::string& surface,
                                   const PropertiesStage& stage);

// The title of a stage's pictures: "G network, porosity 0.7000" or "G sheet, ...".
std::string properties_title(const std::string& surface, const nlohmann::json& properties);

}  // namespace cmcsurf
