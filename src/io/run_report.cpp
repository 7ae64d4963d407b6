#include "io/run_report.h"

#include <sys/resource.h>

#include <algorithm>
#include <limits>
#include <set>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "common/atomic_file.h"
#include "io/build_info.h"
#include "io/csv.h"
#include "parallel/threads.h"
#include "mesh/morphometry.h"
#include "model/run_options.h"
#include "model/run_schema.h"
#include "science/crystallographic_cell.h"
#include "surfaces/initial.h"

namespace cmcsurf {

nlohmann::json params_json(const RunParams& p) {
  nlohmann::json j = nlohmann::json::object();
  for (const RunOption& o : run_option_table())
    std::visit([&](const auto& v) { j[o.key] = v; }, run_option_value(o, p));
  return j;
}

RunParams params_from_json(const nlohmann::json& j, const RunParams& base) {
  RunParams p = base;
  for (const RunOption& o : run_option_table()) {
    if (o.optional_in_json && !j.contains(o.key)) continue;
    if (!j.is_object() || !j.contains(o.key))
      throw std::runtime_error(fmt::format("parameter '{}' is missing", o.key));
    const std::string what = fmt::format("parameter '{}'", o.key);
    std::visit(
        [&](const auto& ref) {
          using R = std::decay_t<decltype(ref)>;
          if constexpr (std::is_same_v<R, RunChoice>) {
            const std::string s = json_value<std::string>(j.at(o.key), what);
            if (!set_run_choice(o, p, s))
              throw std::runtime_error(fmt::format("parameter '{}': '{}' is none of {}", o.key,
                                                   s, run_choice_names(o)));
          } else {
            auto& v = ref(p);
            v = json_value<std::remove_cvref_t<decltype(v)>>(j.at(o.key), what);
          }
        },
        o.ref);
  }
  try {
    check_run_params(p, true);  // the command line's own checks (model/run_options.h)
  } catch (const OptionError& e) {
    throw std::runtime_error(fmt::format("parameter out of range: {}", e.what()));
  }
  return p;
}

nlohmann::json measures_json(const Measures& m, bool curvature_integrals) {
  // NaN (an error estimate not computed) is written as null.
  auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  nlohmann::json j;
  if (m.sharp) {
    j["area"] = m.area;
    j["area_error"] = number(m.area_error);
    j["mean_curvature"] = m.mean_curvature;
    j["mean_curvature_error"] = number(m.mean_curvature_error);
    j["total_mean_curvature"] = m.total_mean_curvature;
    j["euler_characteristic"] = m.euler_characteristic;
    j["genus"] = 1 - m.euler_characteristic;
    const std::int64_t chi = m.euler_characteristic_surface();
    auto count = [](std::int64_t c) { return c >= 0 ? nlohmann::json(c) : nlohmann::json(); };
    j["euler_characteristic_phase1"] = m.euler_characteristic;
    j["euler_characteristic_phase2"] = m.euler_characteristic_phase2;
    j["euler_characteristic_surface"] = chi;
    j["components_phase1"] = count(m.components_phase1);
    j["components_phase2"] = count(m.components_phase2);
    j["surface_components"] = count(m.surface_components);
    const double pieces = double(m.surface_components);
    j["genus_surface"] = m.surface_components > 0 ? nlohmann::json(1.0 - 0.5 * double(chi) / pieces)
                                                  : nlohmann::json();
    if (curvature_integrals) {
      j["homogeneity_index"] = number(homogeneity_index(m.area, chi));
      j["gaussian_curvature_integral"] = m.gaussian_curvature_integral;
      const double gauss_bonnet = 2.0 * std::numbers::pi * double(chi);
      const double gb_error = m.gaussian_curvature_integral / gauss_bonnet - 1.0;
      j["gauss_bonnet_error"] = chi != 0 ? nlohmann::json(gb_error) : nlohmann::json();
      j["mean_gaussian_curvature"] = m.area > 0 ? m.gaussian_curvature_integral / m.area : 0.0;
      j["willmore_energy"] = m.willmore_energy;
    }
  }
  j["area_diffuse"] = m.area_diffuse;
  j["mean_curvature_diffuse"] = m.mean_curvature_diffuse;
  j["total_mean_curvature_diffuse"] = m.total_mean_curvature_diffuse;
  j["mean_curvature_mu"] = m.mean_curvature_mu;
  if (m.sharp) j["mean_curvature_mu_gap"] = m.mean_curvature_mu - m.mean_curvature;
  j["volume_fraction"] = m.volume_fraction;
  j["volume_fraction_cells"] = m.volume_fraction_cells;
  j["mass"] = m.mass;
  j["energy"] = m.energy;
  j["equilibrium_residual"] = m.equilibrium_residual;
  return j;
}

namespace {

nlohmann::json parallel_side_json(const std::vector<ParallelSurface>& side) {
  nlohmann::json a = nlohmann::json::array();
  for (const ParallelSurface& ps : side)
    a.push_back({{"distance", ps.distance},
                 {"area", ps.area},
                 {"volume", ps.volume},
                 {"area_steiner", ps.area_steiner},
                 {"volume_steiner", ps.volume_steiner}});
  return a;
}

// The cell geometry's keys: channel_radius, parallel_surfaces, lipid (with its options),
// geometry_seconds. NaN (no solution) is written as null.
void add_cell_geometry(nlohmann::json& j, const CellGeometry& g, const RunParams& p) {
  auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  j["channel_radius"] = {{"phase1", thickness_json(g.channels.phase1, "unit cell")},
                         {"phase2", thickness_json(g.channels.phase2, "unit cell")}};
  j["parallel_surfaces"] = {
      {"area", g.integrals.area},
      {"total_mean_curvature", g.integrals.total_mean_curvature},
      {"euler_characteristic_surface", g.integrals.euler_characteristic},
      {"phase1", parallel_side_json(g.parallel.phase1)},
      {"phase2", parallel_side_json(g.parallel.phase2)}};
  if (g.lipid) {
    nlohmann::json l = {{"length_nm", g.lipid->length_nm},
                        {"volume_fraction", g.lipid->fraction},
                        {"length_ratio", number(g.lipid->ratio_formula)},
                        {"lattice_parameter_nm", number(g.lipid->lattice_nm_formula)},
                        {"length_ratio_measured", number(g.lipid->ratio_measured)},
                        {"lattice_parameter_measured_nm", number(g.lipid->lattice_nm_measured)}};
    if (const auto cell = crystallographic_cell(p.surface)) {
      l["crystallographic_lattice_parameter_nm"] =
          number(g.lipid->lattice_nm_formula * cell->lattice_ratio);
      l["crystallographic_lattice_parameter_measured_nm"] =
          number(g.lipid->lattice_nm_measured * cell->lattice_ratio);
    }
    j["lipid"] = l;
  }
  j["geometry_seconds"] = g.seconds;
}

void add_cell_geometry_conventions(nlohmann::json& j) {
  j["conventions"]["channel_radius"] =
      "per phase (phase1: phi > 1/2): at each cell of the phase, the radius of the largest ball "
      "inside the phase that contains it (half of scaffold's local thickness; mean, std, min, "
      "max = the largest inscribed sphere, volume-weighted p5/p50/p95, a histogram), in units of "
      "the computed cell; voxel resolution, about h/2";
  j["conventions"]["parallel_surfaces"] =
      "for each distance l (--parallel-distances, cell units) and side (phase1: the parallel "
      "surface inside phase 1, phase2: inside phase 2): the area of {d = l} and the volume "
      "between the surface and it, d the exact distance to the sharp surface's mesh; "
      "area_steiner = A -+ 2 (int H dA) l + 2 pi chi l^2 and volume_steiner = A l -+ (int H dA) "
      "l^2 + 2 pi chi l^3 / 3 (- on the phase-1 side; valid while the normals do not meet)";
  j["conventions"]["lipid"] =
      "--lipid-length l (nm) and --lipid-fraction phi_L: the x = l / a with phi_L = 2 "
      "sigma x + (4 pi / 3) chi x^3 (sigma, chi of the computed cell: length_ratio, "
      "lattice_parameter_nm = l / x; crystallographic_*: a_c of crystallographic_cell) and "
      "with phi_L the measured volume fraction of {|d| < x} (the *_measured keys)";
}

}  // namespace

std::uint64_t peak_memory_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return 1024 * std::uint64_t(usage.ru_maxrss);  // Linux reports kilobytes
}

nlohmann::json run_report(const RunParams& p, const RunResult& r, int threads) {
  const SurfaceInfo* info = find_surface(p.surface);
  const bool nodal = is_nodal_surface(p.surface);
  nlohmann::json j;
  j["version"] = CMCSURF_VERSION;
  j["build"] = build_info_json();  // what a checkpoint must share (io/build_info.h)
  j["surface"] = p.surface;
  j["grid"] = p.grid;
  j["h"] = p.h();
  j["epsilon"] = p.epsilon;
  j["dt"] = p.dt();
  j["volume_fraction_target"] = nodal ? nlohmann::json(p.volume_fraction) : nlohmann::json();
  j["steps"] = r.steps;
  j["prerelax_steps"] = r.prerelax_steps;
  j["time"] = r.history.empty() ? 0.0 : r.history.back().time;
  j["vcycles"] = r.vcycles;
  j["coarse_steps"] = r.coarse_steps;
  const int all_steps = r.steps + r.prerelax_steps + r.coarse_steps;
  j["vcycles_per_step"] = all_steps ? double(r.vcycles) / all_steps : 0.0;
  j["seconds_per_vcycle"] = r.vcycles ? r.solver_seconds / double(r.vcycles) : 0.0;
  double dt_max = 0.0;
  for (const StepRecord& s : r.history) dt_max = std::max(dt_max, s.dt);
  j["dt_max"] = dt_max;  // differs from dt with --dt-max-factor (adaptive steps)
  // Peak resident memory of the process so far (Linux reports kilobytes), and per finest cell.
  const double peak = double(peak_memory_bytes());
  j["peak_memory_bytes"] = peak;
  j["peak_memory_bytes_per_cell"] = peak / (double(p.grid) * p.grid * p.grid);
  j["unconverged_steps"] = r.unconverged_steps;
  j["converged"] = r.converged;
  j["stop_reason"] = r.stop_reason;
  const nlohmann::json final_measures = measures_json(r.final);
  for (auto& [key, value] : final_measures.items()) j[key] = value;
  j["final_d_area"] = r.history.empty() ? 0.0 : r.history.back().d_area;
  j["final_d_phi"] = r.history.empty() ? 0.0 : r.history.back().d_phi;
  if (r.euler_characteristic_start && r.final.sharp) {  // the family's topology, the member's
    j["euler_characteristic_start"] = *r.euler_characteristic_start;
    j["topology_changed"] = *r.euler_characteristic_start != r.final.euler_characteristic;
  }
  j["initial"] = measures_json(r.initial, false);
  if (const auto cell = crystallographic_cell(p.surface); cell && r.final.sharp) {
    const std::int64_t chi = r.final.euler_characteristic_surface();
    const double mean_k = r.final.gaussian_curvature_integral / r.final.area;
    const CellNumbers c =
        per_crystallographic_cell(*cell, r.final.area, chi, r.final.mean_curvature, mean_k);
    j["crystallographic_cell"] = {
        {"space_group", cell->space_group},
        {"space_group_phase1", cell->space_group_phase1},
        {"cells_per_computed_cell", cell->cells_per_computed_cell},
        {"lattice_parameter", cell->lattice_ratio},
        {"area", c.area},
        {"euler_characteristic_surface", c.euler_characteristic},
        {"mean_curvature", c.mean_curvature},
        {"mean_gaussian_curvature", c.mean_gaussian_curvature},
        {"computed_cell",
         {{"lattice_parameter", 1.0},
          {"area", r.final.area},
          {"euler_characteristic_surface", chi},
          {"mean_curvature", r.final.mean_curvature},
          {"mean_gaussian_curvature", mean_k}}}};
  }
  if (r.bisection) {
    j["bisection"] = {{"beta", r.bisection->beta},
                      {"v_ave", r.bisection->v_ave},
                      {"iterations", r.bisection->iterations},
                      {"mass_before_shift", r.mass_before_shift}};
  }
  j["constrain"] = constraint_name(p.constrain);
  if (r.volume_constrained) {
    nlohmann::json iterates = nlohmann::json::array();
    for (const VolumeIterate& it : r.volume_iterates)
      iterates.push_back({{"mass", it.mass},
                          {"volume_fraction", it.volume_fraction},
                          {"steps", it.steps},
                          {"relaxed", it.relaxed}});
    j["volume_corrections"] = int(r.volume_iterates.size()) - 1;
    j["volume_iterates"] = iterates;
    j["volume_converged"] = r.volume_converged;
    j["volume_steps"] = r.volume_steps;
    j["volume_seconds"] = r.volume_seconds;
  } else {
    j["volume_corrections"] = 0;
    j["constrain_note"] =
        !nodal ? "no effect: this surface has no target volume fraction"
        : p.constrain == Constraint::kComponents
            ? "components: each component of phase 1 holds its sharp volume after every step "
              "(component_volume_targets, summing to alpha)"
            : "mass: the mass is held at alpha (Section 4.4); volume_fraction may differ from it";
  }
  // Double structures: each piece of the surface, the components' volumes, the warnings.
  if (r.final.sharp && !r.interfaces.empty()) {
    nlohmann::json pieces = nlohmann::json::array();
    for (const InterfaceMeasures& m : r.interfaces)
      pieces.push_back({{"phase", m.phase},
                        {"component", m.component},
                        {"area", m.area},
                        {"mean_curvature", m.mean_curvature},
                        {"mean_curvature_std", m.mean_curvature_std},
                        {"gaussian_curvature_integral", m.gaussian_curvature_integral},
                        {"euler_characteristic", m.euler_characteristic},
                        {"enclosed_volume", m.enclosed_volume}});
    j["interfaces"] = pieces;
  }
  if (!r.component_volume_targets.empty()) {
    j["component_volume_targets"] = r.component_volume_targets;
    j["component_volumes"] = r.component_volumes;
  }
  j["warnings"] = r.warnings;
  // The cell geometry (pipeline/cell_geometry.h): channel radii, parallel surfaces, lipids.
  if (r.geometry) add_cell_geometry(j, *r.geometry, p);
  j["balanced"] = info ? nlohmann::json(info->balanced) : nlohmann::json();
  j["wall_seconds"] = r.wall_seconds;
  j["solver_seconds"] = r.solver_seconds;
  j["measure_seconds"] = r.measure_seconds;
  j["threads"] = threads;
  // Under mpirun: every rank's OpenMP threads (parallel/threads.h), rank 0's are `threads`.
  if (threads_per_rank().size() > 1) j["threads_per_rank"] = threads_per_rank();
  j["parameters"] = params_json(p);
  // What the keys mean: the report key table's help of the keys it marks (schema/).
  nlohmann::json conventions = {{"phase_1", "phi > 1/2"}};
  for (const ReportKey& k : report_key_table())
    if (k.convention) conventions[std::string(k.key)] = std::string(k.help);
  j["conventions"] = conventions;
  if (r.geometry) add_cell_geometry_conventions(j);
  return j;
}

std::string stage_text(const StepRecord& r) {
  std::string text(run_stage_name(r.stage));
  for (int grid : r.coarse_grids) text += fmt::format("@{}", grid);
  return text;
}

HistoryValue history_value(const StepRecord& r, HistoryColumn c) {
  switch (c) {
    case HistoryColumn::kStep: return static_cast<long long>(r.step);
    case HistoryColumn::kStage: return stage_text(r);
    case HistoryColumn::kTime: return r.time;
    case HistoryColumn::kArea: return r.area;
    case HistoryColumn::kDArea: return r.d_area;
    case HistoryColumn::kDPhi: return r.d_phi;
    case HistoryColumn::kEnergy: return r.energy;
    case HistoryColumn::kMass: return r.mass;
    case HistoryColumn::kVcycles: return static_cast<long long>(r.vcycles);
    case HistoryColumn::kResidual: return r.residual;
    case HistoryColumn::kElapsed: return r.elapsed;
    case HistoryColumn::kDt: return r.dt;
    case HistoryColumn::kVolumeFraction: return r.volume_fraction;
    case HistoryColumn::kEquilibriumResidual: return r.equilibrium_residual;
  }
  throw std::logic_error("history_value: a column without a case");
}

namespace {

// "relax@16@32" -> relax, {16, 32}.
void set_stage(StepRecord& r, const std::string& text) {
  std::size_t at = text.find('@');
  const auto stage = parse_run_stage(std::string_view(text).substr(0, at));
  if (!stage) throw std::runtime_error(fmt::format("unknown stage '{}'", text));
  r.stage = *stage;
  r.coarse_grids.clear();
  while (at != std::string::npos) {
    const std::size_t next = text.find('@', at + 1);
    const std::string grid = text.substr(at + 1, next == std::string::npos ? next : next - at - 1);
    std::size_t used = 0;
    int n = 0;
    try {
      n = std::stoi(grid, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != grid.size() || n < 2)
      throw std::runtime_error(fmt::format("unknown stage '{}' (a grid after '@')", text));
    r.coarse_grids.push_back(n);
    at = next;
  }
}

}  // namespace

void set_history_value(StepRecord& r, HistoryColumn c, const nlohmann::json& v) {
  switch (c) {
    case HistoryColumn::kStep: v.get_to(r.step); return;
    case HistoryColumn::kStage: set_stage(r, v.get<std::string>()); return;
    case HistoryColumn::kTime: v.get_to(r.time); return;
    case HistoryColumn::kArea: v.get_to(r.area); return;
    case HistoryColumn::kDArea: v.get_to(r.d_area); return;
    case HistoryColumn::kDPhi: v.get_to(r.d_phi); return;
    case HistoryColumn::kEnergy: v.get_to(r.energy); return;
    case HistoryColumn::kMass: v.get_to(r.mass); return;
    case HistoryColumn::kVcycles: v.get_to(r.vcycles); return;
    case HistoryColumn::kResidual: v.get_to(r.residual); return;
    case HistoryColumn::kElapsed: v.get_to(r.elapsed); return;
    case HistoryColumn::kDt: v.get_to(r.dt); return;
    case HistoryColumn::kVolumeFraction: v.get_to(r.volume_fraction); return;
    case HistoryColumn::kEquilibriumResidual:  // JSON keeps a NaN as null
      r.equilibrium_residual =
          v.is_null() ? std::numeric_limits<double>::quiet_NaN() : v.get<double>();
      return;
  }
  throw std::logic_error("set_history_value: a column without a case");
}

std::string history_csv(const std::vector<StepRecord>& history) {
  const std::vector<HistoryColumnInfo>& columns = history_column_table();
  std::string out = history_header() + "\n";
  for (const StepRecord& r : history) {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (c > 0) out += ',';
      std::visit([&](const auto& v) { out += fmt::format(fmt::runtime(columns[c].format), v); },
                 history_value(r, columns[c].id));
    }
    out += '\n';
  }
  return out;
}

void write_history_csv(const std::filesystem::path& path, const std::vector<StepRecord>& history) {
  write_file_atomic(path, history_csv(history));
}

nlohmann::json quality_json(const CmcQuality& q, double relaxed_area) {
  const nlohmann::json null;
  auto nodal = [&](double v) { return q.has_nodal ? nlohmann::json(v) : null; };
  const nlohmann::json excess =
      q.has_nodal && relaxed_area > 0.0 ? nlohmann::json(q.nodal_area / relaxed_area - 1.0) : null;
  return {{"mean_curvature_local_mean", q.relaxed.mean},
          {"mean_curvature_std", q.relaxed.std},
          {"area_iso", relaxed_area},  // alias of area (both are the sharp estimate)
          {"nodal_level", nodal(q.nodal_level)},
          {"nodal_volume_fraction", nodal(q.nodal_volume_fraction)},
          {"nodal_area", nodal(q.nodal_area)},
          {"nodal_area_iso", nodal(q.nodal_area)},  // alias of nodal_area
          {"nodal_area_diffuse", nodal(q.nodal_area_diffuse)},
          {"nodal_area_tanh", nodal(q.nodal_area_diffuse)},  // its earlier name
          {"nodal_relax_steps", q.has_nodal ? nlohmann::json(0) : null},  // no longer relaxed
          {"nodal_mean_curvature", nodal(q.nodal_mean_curvature)},
          {"nodal_mean_curvature_diffuse", nodal(q.nodal_mean_curvature_diffuse)},
          {"nodal_mean_curvature_local_mean", nodal(q.nodal.mean)},
          {"nodal_mean_curvature_std", nodal(q.nodal.std)},
          {"nodal_std_ratio", q.has_nodal && q.relaxed.std > 0.0
                                  ? nlohmann::json(q.nodal.std / q.relaxed.std) : null},
          {"nodal_area_excess", excess},
          {"nodal_area_excess_iso", excess},  // alias of nodal_area_excess
          {"quality_seconds", q.seconds}};
}

std::string curvature_histogram_csv(const CmcQuality& q) {
  std::string out = "H_lo,H_hi,relaxed,nodal\n";
  for (std::size_t b = 0; b + 1 < q.edges.size(); ++b)
    out += fmt::format("{:.17g},{:.17g},{:.17g},{}\n", q.edges[b], q.edges[b + 1],
                       q.relaxed_hist[b],
                       q.has_nodal ? fmt::format("{:.17g}", q.nodal_hist[b]) : std::string());
  return out;
}

void write_curvature_histogram_csv(const std::filesystem::path& path, const CmcQuality& q) {
  write_file_atomic(path, curvature_histogram_csv(q));
}

void write_curvature_distribution_csv(const std::filesystem::path& path, const CmcQuality& q) {
  const OwnRangeHistogram& h = q.relaxed_h_own;
  const OwnRangeHistogram& k = q.relaxed_k_own;
  std::string out = "bin,H_lo,H_hi,H_fraction,K_lo,K_hi,K_fraction\n";
  for (std::size_t b = 0; b < h.fraction.size() && b < k.fraction.size(); ++b)
    out += fmt::format("{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", b, h.edges[b],
                       h.edges[b + 1], h.fraction[b], k.edges[b], k.edges[b + 1], k.fraction[b]);
  write_file_atomic(path, out);
}

namespace {

CsvCell json_cell(const nlohmann::json& v) {
  if (v.is_string()) return CsvCell(v.get<std::string>());
  if (v.is_boolean()) return CsvCell(v.get<bool>() ? "true" : "false");
  if (v.is_number_integer()) return CsvCell(v.get<long long>());
  if (v.is_number()) return CsvCell(v.get<double>());
  return CsvCell("");
}

}  // namespace

std::string sweep_csv(const std::vector<nlohmann::json>& reports) {
  std::vector<std::string> header;
  std::set<std::string> seen;
  auto add = [&](const std::string& key) {
    if (seen.insert(key).second) header.push_back(key);
  };
  for (std::string_view key : sweep_leading_columns()) add(std::string(key));
  for (const nlohmann::json& r : reports)
    for (auto it = r.begin(); it != r.end(); ++it)
      if (!it->is_object() && !it->is_array()) add(it.key());
  CsvWriter csv(header);
  for (const nlohmann::json& r : reports) {
    std::vector<CsvCell> row;
    for (const std::string& key : header)
      row.push_back(r.contains(key) ? json_cell(r[key]) : CsvCell(""));
    csv.add_row(row);
  }
  return csv.str();
}

}  // namespace cmcsurf
