#include "pipeline/properties_stage.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "common/wall_clock.h"
#include "properties/cell_properties.h"
#include "properties/solid_fraction.h"
#include "surfaces/initial.h"

namespace cmcsurf {

namespace {

using properties::CellProperties;
using properties::WallShearStats;
using properties::Matrix3;
using properties::Matrix6;
using properties::Vector3;

nlohmann::json to_json(const Vector3& v) { return {v[0], v[1], v[2]}; }
nlohmann::json to_json(const Matrix3& m) { return {to_json(m[0]), to_json(m[1]), to_json(m[2])}; }
nlohmann::json to_json(const Matrix6& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& row : m)
    rows.push_back(nlohmann::json(std::vector<double>(row.begin(), row.end())));
  return rows;
}

nlohmann::json solver_json(const properties::LoadCaseStats* cases, int count, bool converged,
                           double seconds, std::size_t bytes) {
  nlohmann::json iterations = nlohmann::json::array(), residuals = nlohmann::json::array();
  for (int c = 0; c < count; ++c) {
    iterations.push_back(cases[c].iterations);
    residuals.push_back(cases[c].relative_residual);
  }
  return {{"iterations", iterations},
          {"relative_residual", residuals},
          {"converged", converged},
          {"seconds", seconds},
          {"memory_bytes", bytes}};
}

// The superficial velocity of the request in m/s (NaN when no flow is given).
double superficial_velocity(const PropertiesRequest& r) {
  if (std::isfinite(r.velocity_mm_s)) return r.velocity_mm_s * 1e-3;
  const double m = metres_per_unit(r.units);
  if (std::isfinite(r.flow_rate_ml_min) && std::isfinite(r.flow_area) && std::isfinite(m))
    return r.flow_rate_ml_min * 1e-6 / 60.0 / (r.flow_area * m * m);
  return NAN;
}

// Flow keys (docs/properties.md, "Flow"): permeability in cell-size^2 (the solver's voxel^2
// / n^2) and m^2 when the units are known; wall shear stress normalised by mu U / L (U the
// superficial velocity, L the cell size) and, for a given flow, in mPa with the pressure drop.
void add_flow_keys(nlohmann::json& j, const CellProperties& p, const PropertiesRequest& r) {
  const double n2 = double(p.n) * p.n;
  Matrix3 k = p.flow.permeability;
  for (auto& row : k)
    for (double& x : row) x /= n2;
  j["permeability"] = to_json(k);
  const double m = metres_per_unit(r.units), cell_m = r.cell_size * m;
  if (std::isfinite(cell_m)) {
    Matrix3 km = k;
    for (auto& row : km)
      for (double& x : row) x *= cell_m * cell_m;
    j["permeability_m2"] = to_json(km);
  }
  j["hydraulic_tortuosity"] = to_json(p.flow.hydraulic_tortuosity);
  j["specific_surface"] = p.specific_surface * p.n;  // per cell size
  j["kozeny_carman_constant"] = p.kozeny_carman_constant;
  j["closed_pore_fraction"] = p.flow.closed_pore_fraction;
  j["flow_percolates"] = p.flow.percolates;
  // tau in solver units (mu = 1, unit gradient, h = 1) times mu U / (k_aa h) for the flow
  // along a: with L = n h, tau L / (mu U) = tau_solver n / k_aa,solver.
  const double u = superficial_velocity(r);
  const bool given_flow = std::isfinite(u) && std::isfinite(cell_m);
  const double to_mpa = r.viscosity_mpa_s * 1e-3 * u / cell_m * 1e3;  // mPa per mu U / L
  const char* stats[] = {"mean", "median", "p5", "p95", "max"};
  const char* axis_name[] = {"x", "y", "z"};
  auto normalised = [&](int a) {
    const WallShearStats& w = p.wall_shear_axes[a];
    const double to_normalised = double(p.n) / p.flow.permeability[a][a];
    return nlohmann::json{{"mean", w.mean * to_normalised},
                          {"median", w.median * to_normalised},
                          {"p5", w.p5 * to_normalised},
                          {"p95", w.p95 * to_normalised},
                          {"max", w.max * to_normalised},
                          {"histogram", w.histogram}};
  };
  auto in_mpa = [&](const nlohmann::json& tau) {
    nlohmann::json mpa = {{"superficial_velocity_m_s", u}};
    for (const char* key : stats) mpa[key] = tau[key].get<double>() * to_mpa;
    if (tau.contains("histogram")) mpa["histogram"] = tau["histogram"];
    return mpa;
  };
  // Per axis with flow, and the statistics' means over those axes (a cubic cell's three agree).
  nlohmann::json per_axis = nlohmann::json::object(), per_axis_mpa = nlohmann::json::object();
  nlohmann::json axis_mean = nlohmann::json::object();
  nlohmann::json drop = nlohmann::json::array();
  int axes = 0;
  for (int a = 0; a < 3; ++a) {
    const double kaa = p.flow.permeability[a][a];
    if (!(kaa > 0.0 && p.wall_shear_axes[a].wall_area > 0.0)) {
      drop.push_back(nullptr);
      continue;
    }
    const nlohmann::json tau = normalised(a);
    per_axis[axis_name[a]] = tau;
    for (const char* key : stats)
      axis_mean[key] = axis_mean.value(key, 0.0) + tau[key].get<double>();
    if (given_flow) per_axis_mpa[axis_name[a]] = in_mpa(tau);
    // Darcy: dP/dx_a = mu U / k_aa.
    drop.push_back(given_flow ? nlohmann::json(r.viscosity_mpa_s * 1e-3 * u /
                                               (k[a][a] * cell_m * cell_m))
                              : nlohmann::json(nullptr));
    ++axes;
  }
  if (axes > 0) {
    for (const char* key : stats) axis_mean[key] = axis_mean[key].get<double>() / axes;
    axis_mean["axes"] = axes;
    j["wall_shear_stress_per_axis"] = per_axis;
    j["wall_shear_stress_axis_mean"] = axis_mean;
    if (given_flow) {
      j["wall_shear_stress_mpa_per_axis"] = per_axis_mpa;
      nlohmann::json mean_mpa = in_mpa(axis_mean);
      mean_mpa["axes"] = axes;
      j["wall_shear_stress_mpa_axis_mean"] = mean_mpa;
      j["pressure_drop_pa_per_m_per_axis"] = drop;
    }
  }
  // The flow along z alone: the earlier keys, kept for users' scripts.
  if (k[2][2] > 0.0 && p.wall_shear.wall_area > 0.0) {
    nlohmann::json tau = normalised(2);
    tau["axis"] = "z";
    tau["normalisation"] = "mu U / L (U superficial velocity, L cell size)";
    j["wall_shear_stress"] = tau;
    if (given_flow) {
      nlohmann::json mpa = in_mpa(tau);
      mpa["axis"] = "z";
      j["wall_shear_stress_mpa"] = mpa;
      j["pressure_drop_pa_per_m"] = r.viscosity_mpa_s * 1e-3 * u / (k[2][2] * cell_m * cell_m);
    }
  }
}

// The keys of one solid's properties (docs/properties.md names them). E: the solid's Young's
// modulus in GPa (NaN: only the normalised values).
nlohmann::json cell_json(const CellProperties& p, const PropertiesRequest& r, double e_gpa) {
  nlohmann::json j;
  j["relative_density"] = p.relative_density;
  j["porosity"] = p.porosity;
  j["grid"] = p.n;
  if (r.elastic) {
    const auto& c = p.constants;
    j["stiffness_voigt"] = to_json(p.elastic.stiffness_voigt);
    j["youngs_modulus"] = to_json(c.youngs_modulus);
    j["shear_modulus"] = to_json(c.shear_modulus);
    j["poisson_ratio"] = {c.poisson_ratio[0][1], c.poisson_ratio[1][2], c.poisson_ratio[2][0]};
    j["bulk_modulus"] = c.bulk_modulus;
    j["zener_ratio"] = c.zener_ratio;
    j["youngs_modulus_min"] = c.youngs_modulus_min;
    j["youngs_modulus_min_direction"] = to_json(c.direction_min);
    j["youngs_modulus_max"] = c.youngs_modulus_max;
    j["youngs_modulus_max_direction"] = to_json(c.direction_max);
    if (std::isfinite(e_gpa)) {
      Matrix6 gpa = p.elastic.stiffness_voigt;
      for (auto& row : gpa)
        for (double& x : row) x *= e_gpa;
      j["stiffness_voigt_gpa"] = to_json(gpa);
      Vector3 e = c.youngs_modulus, g = c.shear_modulus;
      for (int a = 0; a < 3; ++a) e[a] *= e_gpa, g[a] *= e_gpa;
      j["youngs_modulus_gpa"] = to_json(e);
      j["shear_modulus_gpa"] = to_json(g);
      j["bulk_modulus_gpa"] = c.bulk_modulus * e_gpa;
      j["youngs_modulus_min_gpa"] = c.youngs_modulus_min * e_gpa;
      j["youngs_modulus_max_gpa"] = c.youngs_modulus_max * e_gpa;
    }
  }
  nlohmann::json bound = {{"bulk_modulus", p.bound_solid.bulk_modulus},
                          {"shear_modulus", p.bound_solid.shear_modulus},
                          {"youngs_modulus", p.bound_solid.youngs_modulus}};
  nlohmann::json reached = {{"bulk_modulus", p.bulk_fraction_of_bound},
                            {"shear_modulus", p.shear_fraction_of_bound},
                            {"youngs_modulus", p.youngs_fraction_of_bound}};
  if (r.conductivity) {
    j["conductivity_solid"] = to_json(p.solid_conduction.conductivity);
    j["conductivity_pore"] = to_json(p.pore_conduction.conductivity);
    j["formation_factor"] = to_json(p.formation_factor);
    j["tortuosity_pore"] = to_json(p.tortuosity_pore);
    bound["conductivity_solid"] = p.bound_solid.conductivity;
    bound["conductivity_pore"] = p.bound_conductivity_pore;
    reached["conductivity_solid"] = p.conductivity_solid_fraction_of_bound;
    reached["conductivity_pore"] = p.conductivity_pore_fraction_of_bound;
  }
  if (!r.elastic)
    for (const char* k : {"bulk_modulus", "shear_modulus", "youngs_modulus"}) {
      bound.erase(k);
      reached.erase(k);
    }
  j["hashin_shtrikman_upper"] = bound;
  j["fraction_of_bound"] = reached;
  if (r.flow) add_flow_keys(j, p, r);
  j["percolates"] = {{"solid", p.solid_percolates}, {"pore", p.pore_percolates}};
  j["warnings"] = p.warnings;
  nlohmann::json solver = {{"tolerance", r.tolerance}};
  if (r.elastic)
    solver["elastic"] = solver_json(p.elastic.load_cases.data(), 6, p.elastic.converged,
                                    p.elastic.seconds, p.elastic.bytes);
  if (r.conductivity) {
    solver["conductivity_solid"] =
        solver_json(p.solid_conduction.load_cases.data(), 3, p.solid_conduction.converged,
                    p.solid_conduction.seconds, p.solid_conduction.bytes);
    solver["conductivity_pore"] =
        solver_json(p.pore_conduction.load_cases.data(), 3, p.pore_conduction.converged,
                    p.pore_conduction.seconds, p.pore_conduction.bytes);
  }
  if (r.flow) {
    solver["flow"] = solver_json(p.flow.load_cases.data(), 3, p.flow.converged, p.flow.seconds,
                                 p.flow.bytes);
    solver["flow"]["preconditioner_shift"] = p.flow.sigma;
  }
  solver["removed_solid_fraction"] = p.elastic.removed_solid_fraction;
  j["solver"] = solver;
  j["seconds"] = p.seconds;
  return j;
}

// fine + (fine - coarse) / (2^p - 1) element by element, and |fine - limit| as the error.
nlohmann::json richardson_error(const nlohmann::json& fine, const nlohmann::json& coarse) {
  if (fine.is_number())
    return std::abs(fine.get<double>() - properties::richardson_limit(fine.get<double>(),
                                                                      coarse.get<double>()));
  nlohmann::json e = nlohmann::json::array();
  for (std::size_t i = 0; i < fine.size(); ++i) e.push_back(richardson_error(fine[i], coarse[i]));
  return e;
}

constexpr const char* kCheckedKeys[] = {
    "stiffness_voigt", "youngs_modulus", "shear_modulus", "poisson_ratio",    "bulk_modulus",
    "zener_ratio",     "conductivity_solid", "conductivity_pore", "tortuosity_pore",
    "permeability",    "hydraulic_tortuosity"};

// One solid's properties, with the grid check's *_error keys when asked.
nlohmann::json solid_properties(const VoxelSolid& v, const PropertiesRequest& r,
                                const std::function<void(const std::string&)>& progress,
                                const std::string& what) {
  properties::CellPropertiesOptions o;
  o.poisson_ratio = r.poisson_ratio;
  o.elasticity = r.elastic;
  o.conductivity = r.conductivity;
  o.flow = r.flow;
  o.solver.tolerance = r.tolerance;
  const int n = v.fraction.n();
  const std::vector<double> s = properties::voxel_values(v.fraction);
  if (progress) progress(fmt::format("{}: {}^3 voxels, relative density {:.4f}", what, n,
                                     v.solid_fraction));
  if (!r.grid_check)
    return cell_json(properties::compute_cell_properties(n, s, o), r, r.youngs_modulus_gpa);
  const properties::GridCheck g = properties::grid_check(n, s, o);
  nlohmann::json j = cell_json(g.fine, r, r.youngs_modulus_gpa);
  const nlohmann::json coarse = cell_json(g.coarse, r, r.youngs_modulus_gpa);
  for (const char* key : kCheckedKeys)
    if (j.contains(key)) j[std::string(key) + "_error"] = richardson_error(j[key], coarse[key]);
  j["grid_check"] = {{"coarse_grid", g.coarse.n},
                     {"order", properties::kGridCheckOrder},
                     {"coarse_relative_density", g.coarse.relative_density},
                     {"seconds", g.coarse.seconds}};
  return j;
}

void describe_solid(nlohmann::json& j, const SolidSpec& spec, const VoxelSolid& v,
                    const PropertiesRequest& r) {
  j["solid"] = spec.kind == SolidKind::kSheet ? "sheet" : "network";
  if (spec.kind == SolidKind::kNetwork) j["phase"] = spec.other_phase ? 2 : 1;
  if (spec.kind == SolidKind::kSheet && v.thickness > 0.0) {
    j["thickness"] = v.thickness * r.cell_size;
    j["thickness_units"] = r.units;
  }
  if (std::isfinite(v.level)) j["nodal_level"] = v.level;
}

}  // namespace

void set_properties_solid(PropertiesRequest& r, const std::string& solid, long long phase,
                          double porosity, double thickness) {
  if (solid == "network")
    r.solid.kind = SolidKind::kNetwork;
  else if (solid == "sheet")
    r.solid.kind = SolidKind::kSheet;
  else
    throw std::invalid_argument(
        fmt::format("--solid: got '{}'; accepted: network, sheet", solid));
  if (phase != 1 && phase != 2)
    throw std::invalid_argument(fmt::format("--phase: got {}; accepted: 1, 2", phase));
  r.solid.other_phase = phase == 2;
  const bool by_porosity = !std::isnan(porosity), by_thickness = !std::isnan(thickness);
  if (r.solid.kind == SolidKind::kNetwork && (by_porosity || by_thickness))
    throw std::invalid_argument(fmt::format(
        "{}: a network's porosity is its member's (1 - the volume fraction of its phase); "
        "compute the member at the porosity you want (run --volume-fraction), or use --solid "
        "sheet",
        by_porosity ? "--porosity" : "--thickness"));
  if (r.solid.kind == SolidKind::kSheet && by_porosity == by_thickness)
    throw std::invalid_argument(
        "--solid sheet: give exactly one of --porosity P and --thickness T");
  if (by_porosity && !(porosity > 0.0 && porosity < 1.0))
    throw std::invalid_argument(fmt::format("--porosity: got {}; accepted: 0 < P < 1", porosity));
  if (by_thickness && !(thickness > 0.0 && thickness < 0.5 * r.cell_size))
    throw std::invalid_argument(fmt::format(
        "--thickness: got {}; accepted: 0 < T < {} (half a cell of --cell-size {})", thickness,
        0.5 * r.cell_size, r.cell_size));
  r.solid.porosity = by_porosity ? porosity : NAN;
  r.solid.thickness = by_thickness ? thickness : 0.0;
}

double metres_per_unit(const std::string& units) {
  if (units == "um") return 1e-6;
  if (units == "mm") return 1e-3;
  if (units == "cm") return 1e-2;
  if (units == "m") return 1.0;
  if (units == "in") return 0.0254;
  return NAN;
}

void set_properties_only(PropertiesRequest& r, const std::string& only) {
  r.elastic = r.conductivity = r.flow = false;
  std::size_t start = 0;
  while (start <= only.size()) {
    const std::size_t comma = std::min(only.find(',', start), only.size());
    const std::string part = only.substr(start, comma - start);
    if (part == "elastic")
      r.elastic = true;
    else if (part == "conductivity")
      r.conductivity = true;
    else if (part == "flow")
      r.flow = true;
    else
      throw std::invalid_argument(
          fmt::format("--only: got '{}'; accepted: a list of elastic, conductivity, flow", part));
    start = comma + 1;
  }
}

void set_properties_material(PropertiesRequest& r, const std::string& text) {
  if (text.empty()) return;
  const std::size_t comma = text.find(',');
  const std::string e = text.substr(0, comma);
  const std::string nu = comma == std::string::npos ? "" : text.substr(comma + 1);
  auto number = [&](const std::string& part) {
    std::size_t used = 0;
    double v = NAN;
    try {
      v = std::stod(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (part.empty() || used != part.size())
      throw std::invalid_argument(fmt::format(
          "--material: got '{}'; accepted: E_GPa[,nu], e.g. 110,0.34 (Ti-6Al-4V)", text));
    return v;
  };
  const double youngs = number(e);
  const double poisson = comma == std::string::npos ? 0.3 : number(nu);
  r.youngs_modulus_gpa = youngs;
  r.poisson_ratio = poisson;
}

std::string check_properties_request(const PropertiesRequest& r) {
  if (!std::isnan(r.youngs_modulus_gpa) &&
      !(r.youngs_modulus_gpa > 0.0 && r.youngs_modulus_gpa <= 1e4))
    return fmt::format("--material: E {} GPa; accepted: 0 < E <= 1e4", r.youngs_modulus_gpa);
  if (!(r.poisson_ratio > -1.0 && r.poisson_ratio < 0.5))
    return fmt::format("--material: nu {}; accepted: -1 < nu < 0.5", r.poisson_ratio);
  if (!(r.tolerance >= 1e-12 && r.tolerance <= 1e-2))
    return fmt::format("--tolerance: got {}; accepted: 1e-12 to 1e-2", r.tolerance);
  if (!r.elastic && !r.conductivity && !r.flow) return "--only: nothing to compute";
  if (!(r.viscosity_mpa_s > 0.0 && r.viscosity_mpa_s <= 1e6))
    return fmt::format("--viscosity: got {} mPa s; accepted: 0 < mu <= 1e6", r.viscosity_mpa_s);
  const bool rate = !std::isnan(r.flow_rate_ml_min), area = !std::isnan(r.flow_area),
             velocity = !std::isnan(r.velocity_mm_s);
  if (velocity && (rate || area))
    return "--velocity: give either --velocity or --flow-rate with --flow-area, not both";
  if (rate != area) return "--flow-rate and --flow-area: give both (mL/min through units^2)";
  if (rate && !(r.flow_rate_ml_min > 0.0 && std::isfinite(r.flow_rate_ml_min)))
    return fmt::format("--flow-rate: got {} mL/min; accepted: > 0", r.flow_rate_ml_min);
  if (area && !(r.flow_area > 0.0 && std::isfinite(r.flow_area)))
    return fmt::format("--flow-area: got {}; accepted: > 0 ({}^2)", r.flow_area, r.units);
  if (velocity && !(r.velocity_mm_s > 0.0 && std::isfinite(r.velocity_mm_s)))
    return fmt::format("--velocity: got {} mm/s; accepted: > 0", r.velocity_mm_s);
  if ((rate || velocity) && std::isnan(metres_per_unit(r.units)))
    return fmt::format("--flow-rate/--velocity: need a physical --units (um, mm, cm, m, in) and "
                       "--cell-size; got --units {}",
                       r.units);
  if (!(r.cell_size > 0.0 && std::isfinite(r.cell_size)))
    return fmt::format("--cell-size: got {}; accepted: > 0", r.cell_size);
  return {};
}

nlohmann::json compute_properties(const Field& phi, const PropertiesRequest& r,
                                  const std::function<void(const std::string&)>& progress) {
  const auto t0 = WallClock::now();
  if (const std::string why = check_properties_request(r); !why.empty())
    throw std::invalid_argument(why);
  SolidSpec spec = r.solid;
  if (spec.kind == SolidKind::kSheet && !std::isfinite(spec.porosity))
    spec.thickness = r.solid.thickness / r.cell_size;  // the user's units -> unit cells
  if (r.grid_check && (phi.n() % 2 != 0 || phi.n() < 16))
    throw std::invalid_argument(fmt::format(
        "--grid-check: the field's grid {} has no half (accepted: even N >= 16)", phi.n()));
  const VoxelSolid cmc = cmc_voxel_solid(phi, spec);
  if (!(cmc.solid_fraction > 0.0 && cmc.solid_fraction < 1.0))
    throw std::invalid_argument(
        fmt::format("the field's solid fills {} of the cell: there is no surface",
                    cmc.solid_fraction));
  nlohmann::json j = solid_properties(cmc, r, progress, "CMC solid");
  describe_solid(j, spec, cmc, r);
  if (std::isfinite(r.youngs_modulus_gpa))
    j["material"] = {{"youngs_modulus_gpa", r.youngs_modulus_gpa}};
  j["material"]["poisson_ratio"] = r.poisson_ratio;
  j["notation"] =
      "Voigt order 11 22 33 23 13 12 with engineering shear strains; stiffnesses normalised by "
      "the solid's Young's modulus, conductivities by the solid's (the pore's by the fluid's); "
      "youngs_modulus and shear_modulus along x, y, z (shear: yz, xz, xy); poisson_ratio "
      "nu_xy, nu_yz, nu_zx";
  if (r.compare_nodal) {
    if (!is_nodal_surface(r.surface))
      throw std::invalid_argument(fmt::format(
          "--compare-nodal: surface '{}' has no nodal formula to compare with", r.surface));
    SolidSpec twin = spec;
    const VoxelSolid band =
        nodal_voxel_solid(r.surface, phi.n(), twin, cmc.porosity, NodalSheet::kBand);
    j["nodal"] = solid_properties(band, r, progress,
                                  spec.kind == SolidKind::kSheet ? "nodal band" : "nodal network");
    describe_solid(j["nodal"], spec, band, r);
    if (spec.kind == SolidKind::kSheet) {
      const VoxelSolid offset =
          nodal_voxel_solid(r.surface, phi.n(), twin, cmc.porosity, NodalSheet::kOffset);
      j["nodal_offset"] = solid_properties(offset, r, progress, "nodal offset");
      describe_solid(j["nodal_offset"], spec, offset, r);
    }
  }
  j["properties_seconds"] = seconds_since(t0);
  return j;
}

namespace {

double mean3(const nlohmann::json& v) {
  if (v.is_array() && v.size() == 3 && v[0].is_array())  // a 3x3 tensor: its mean diagonal
    return (v[0][0].get<double>() + v[1][1].get<double>() + v[2][2].get<double>()) / 3.0;
  return (v[0].get<double>() + v[1].get<double>() + v[2].get<double>()) / 3.0;
}

void add_summary(nlohmann::json& out, const nlohmann::json& p, const std::string& prefix) {
  if (p.contains("relative_density")) out[prefix + "relative_density"] = p["relative_density"];
  for (const char* key : {"youngs_modulus", "shear_modulus", "poisson_ratio",
                          "conductivity_solid", "conductivity_pore", "tortuosity_pore",
                          "permeability", "hydraulic_tortuosity"}) {
    if (p.contains(key)) out[prefix + key] = mean3(p[key]);
    const std::string error = std::string(key) + "_error";
    if (p.contains(error)) out[prefix + error] = mean3(p[error]);
  }
  for (const char* key : {"bulk_modulus", "zener_ratio"}) {
    if (p.contains(key)) out[prefix + key] = p[key];
    const std::string error = std::string(key) + "_error";
    if (p.contains(error)) out[prefix + error] = p[error];
  }
  // The flow's scalars for the chart's Kozeny-Carman line and the sweep's columns: S per cell
  // size, c, and the mean wall shear stress (mu U / L) averaged over the axes with flow.
  if (p.contains("permeability"))
    for (const char* key : {"specific_surface", "kozeny_carman_constant"})
      if (p.contains(key)) out[prefix + key] = p[key];
  if (p.contains("wall_shear_stress_axis_mean"))
    out[prefix + "wall_shear_stress"] = p["wall_shear_stress_axis_mean"]["mean"];
}

}  // namespace

nlohmann::json properties_summary(const nlohmann::json& properties) {
  nlohmann::json out = nlohmann::json::object();
  add_summary(out, properties, "properties_");
  if (properties.contains("nodal")) add_summary(out, properties["nodal"], "properties_nodal_");
  return out;
}

std::vector<double> parse_properties_porosities(const std::string& text) {
  std::vector<double> out;
  std::size_t start = 0;
  while (!text.empty() && start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string part = text.substr(start, comma - start);
    std::size_t used = 0;
    double v = NAN;
    try {
      v = std::stod(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (part.empty() || used != part.size())
      throw std::invalid_argument(fmt::format(
          "--properties-porosity: got '{}'; accepted: P or a list P1,P2,... with 0 < P < 1",
          text));
    out.push_back(v);
    start = comma + 1;
  }
  if (out.size() > 16)
    throw std::invalid_argument(fmt::format(
        "--properties-porosity: {} porosities; accepted: at most 16", out.size()));
  return out;
}

PropertiesRequest stage_properties_request(const PropertiesStage& stage,
                                           const std::string& surface, int grid) {
  PropertiesRequest request;
  const bool by_porosity = !stage.porosities.empty(),
             by_thickness = !std::isnan(stage.thickness);
  if (stage.solid != "network" && stage.solid != "sheet")
    throw std::invalid_argument(fmt::format(
        "--properties-solid: got '{}'; accepted: network, sheet", stage.solid));
  if (stage.solid == "network" && (by_porosity || by_thickness))
    throw std::invalid_argument(fmt::format(
        "{}: only with --properties-solid sheet (a network's porosity is its member's)",
        by_porosity ? "--properties-porosity" : "--properties-thickness"));
  if (stage.solid == "sheet" && by_porosity == by_thickness)
    throw std::invalid_argument("--properties-solid sheet: give exactly one of "
                                "--properties-porosity P and --properties-thickness T");
  for (double porosity : stage.porosities)
    if (!(porosity > 0.0 && porosity < 1.0))
      throw std::invalid_argument(fmt::format(
          "--properties-porosity: got {}; accepted: 0 < P < 1", porosity));
  if (by_thickness && !(stage.thickness > 0.0 && stage.thickness < 0.5))
    throw std::invalid_argument(fmt::format(
        "--properties-thickness: got {}; accepted: 0 < T < 0.5 (unit cells)", stage.thickness));
  if (stage.grid_check && (grid % 2 != 0 || grid < 16))
    throw std::invalid_argument(fmt::format(
        "--properties-grid-check: the grid {} has no half (accepted: even N >= 16)", grid));
  set_properties_solid(request, stage.solid, 1,
                       by_porosity ? stage.porosities.front() : NAN, stage.thickness);
  request.compare_nodal = stage.nodal;
  request.grid_check = stage.grid_check;
  request.surface = surface;
  return request;
}

nlohmann::json run_properties_keys(const Field& phi, const std::string& surface,
                                   const PropertiesStage& stage) {
  PropertiesRequest request = stage_properties_request(stage, surface, phi.n());
  const nlohmann::json properties = compute_properties(phi, request);
  nlohmann::json keys = properties_summary(properties);
  keys["properties_seconds"] = properties["properties_seconds"];
  keys["properties"] = properties;
  if (stage.porosities.size() > 1) {
    nlohmann::json ramp = nlohmann::json::array();
    double seconds = properties["properties_seconds"].get<double>();
    for (std::size_t i = 0; i < stage.porosities.size(); ++i) {
      request.solid.porosity = stage.porosities[i];
      const nlohmann::json p = i == 0 ? properties : compute_properties(phi, request);
      if (i > 0) seconds += p["properties_seconds"].get<double>();
      nlohmann::json entry = properties_summary(p);
      entry["properties_porosity"] = p["porosity"];
      ramp.push_back(entry);
    }
    keys["properties_ramp"] = ramp;
    keys["properties_seconds"] = seconds;
  }
  return keys;
}

std::string properties_title(const std::string& surface, const nlohmann::json& properties) {
  return fmt::format("{} {}, porosity {:.4f}", surface,
                     properties.value("solid", std::string("network")),
                     properties.value("porosity", NAN));
}

}  // namespace cmcsurf
