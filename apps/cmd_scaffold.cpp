// cmcsurf scaffold: design targets in (surface, porosity, solid, cell size, box), a clean
// printable part out (docs/scaffolds.md). The CMC member is computed, or reused from a cache
// folder keyed by its run parameters.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <tuple>

#include "common/wall_clock.h"
#include "cli_common.h"
#include "commands.h"
#include "common/atomic_file.h"
#include "io/file_checksum.h"
#include "io/file_identity.h"
#include "common/input_file.h"
#include "io/json_file.h"
#include "io/output_folder.h"
#include "io/mesh_output.h"
#include "io/run_report.h"
#include "io/vti.h"
#include "mesh/mesh_size.h"
#include "mesh/scaffold_part.h"
#include "mesh/shape.h"
#include "pipeline/member_topology.h"
#include "report/part_page.h"
#include "pipeline/properties_stage.h"
#include "pipeline/scaffold_compare.h"
#include "pipeline/scaffold_design.h"
#include "mesh_options.h"
#include "run_control.h"

namespace cmcsurf::cli {

namespace {

// About 5 GB of lattice (value, label, mark) before the mesh.
constexpr double kMaxPartNodes = 5.4e8;
// A triangle budget: more than a lattice of kMaxPartNodes could give is no budget.
constexpr long kMaxTriangles = 4'000'000'000L;

struct ScaffoldCommand {
  RunParams params;
  RunOptionStrings strings;
  std::string surface = "G";
  std::string porosity;   // P, or A:B for a ramp along --axis
  std::string axis = "z";
  int graded_members = 0;  // 0: one per 0.1 of porosity, at least 2
  std::string solid = "network";
  double cell_size = 2.0;
  std::string size = "10";
  std::string units = "mm";
  std::string format;
  std::string out;
  std::string cache;
  bool keep_fragments = false;
  long max_triangles = 0;
  double tolerance = 0.0;
  double min_feature = 0.0;
  bool compare_nodal = false;
  bool properties = false;  // --properties: the unit cell's stiffness and conductivities
  std::string material;     // --material E_GPa[,nu]
  bool accept_topology_change = false;
  std::string shape;
  double skin = 0.0;
  CLI::Option* size_option = nullptr;
  // Design from targets (pipeline/scaffold_design.h): V or A:B along --axis.
  std::string target_modulus, target_permeability;
  double pore_size = NAN, min_wall = NAN;
  bool strict_min_wall = false;
  CLI::Option* cell_size_option = nullptr;
  int threads = 0;
  bool quiet = false;
  // Mesh size in the printer's terms (docs/scaffolds.md, "Mesh size").
  double resolution = 0.0;  // --resolution: voxel size in --units (0: --grid decides)
  CLI::Option* tolerance_option = nullptr;
  CLI::Option* grid_option = nullptr;
  bool no_page = false;  // --no-page: no FILE.html, FILE.png
};

// --resolution in place of --grid, and the default chordal tolerance when neither
// --tolerance nor --max-triangles is given. Returns FILE.json's `mesh_size`.
nlohmann::json apply_mesh_size(ScaffoldCommand& cmd, ScaffoldDesign& d) {
  nlohmann::json about;
  if (cmd.resolution != 0.0) {
    if (cmd.grid_option->count() > 0)
      throw UsageError("--resolution: not with --grid (each sets the lattice spacing)");
    if (!(cmd.resolution > 0 && cmd.resolution <= d.cell_size))
      throw UsageError(fmt::format("--resolution: got {}; accepted: 0 < R <= --cell-size ({:g}) "
                                   "in --units", cmd.resolution, d.cell_size));
    try {
      cmd.params.grid = grid_for_resolution(d.cell_size, cmd.resolution, kMaxGrid);
    } catch (const std::invalid_argument& e) {
      throw UsageError(fmt::format("--resolution: {}", e.what()));
    }
    about["resolution"] = cmd.resolution;
  }
  const bool default_tolerance = cmd.tolerance_option->count() == 0 && cmd.max_triangles == 0;
  if (default_tolerance) d.decimate.tolerance = kDefaultChordalToleranceMm / mesh_unit_mm(d.units);
  d.decimate.max_error_samples = kPartErrorSamples;
  about["tolerance"] = d.decimate.tolerance;
  about["tolerance_default"] = default_tolerance;
  about["tolerance_note"] = fmt::format(
      "chordal tolerance in {}; default {:g} mm when neither --tolerance nor --max-triangles "
      "is given (--tolerance 0: not decimated)", d.units, kDefaultChordalToleranceMm);
  about["units"] = d.units;
  return about;
}

// One line every few seconds while a large part is decimated.
DecimateProgress decimate_progress(const ScaffoldCommand& cmd) {
  if (cmd.quiet) return {};
  auto last = std::make_shared<double>(-1.0);
  auto t0 = std::make_shared<std::chrono::steady_clock::time_point>(
      std::chrono::steady_clock::now());
  return [last, t0](DecimateStage stage, int attempt, std::size_t triangles) {
    const double now = seconds_since(*t0);
    if (attempt == 0 && now - *last < 2.0) return;
    *last = now;
    if (stage == DecimateStage::kCollapse && attempt > 0)
      std::cerr << fmt::format("decimating {} triangles (attempt {}, {:.0f} s)\n", triangles,
                               attempt, now);
    else if (stage == DecimateStage::kCollapse)
      std::cerr << fmt::format("  {} triangles left ({:.0f} s)\n", triangles, now);
    else
      std::cerr << fmt::format("  measuring the distance of the {} triangles to the part "
                               "({:.0f} s)\n", triangles, now);
  };
}

// "AxBxC" or "A" in output units, each > 0.
Vec3 parse_size(const std::string& s) {
  const auto bad = [&] {
    return UsageError(fmt::format("--size: got '{}'; accepted: AxBxC or A, numbers {:g} .. {:g} "
                                  "in --units", s, kMinCellSize, kMaxCellSize));
  };
  std::vector<double> parts;
  std::size_t pos = 0;
  for (;;) {
    const std::size_t x = s.find('x', pos);
    const std::string part = s.substr(pos, x == std::string::npos ? std::string::npos : x - pos);
    char* end = nullptr;
    const double v = std::strtod(part.c_str(), &end);
    if (part.empty() || end != part.c_str() + part.size() ||
        !(v >= kMinCellSize && v <= kMaxCellSize))
      throw bad();
    parts.push_back(v);
    if (x == std::string::npos) break;
    pos = x + 1;
  }
  if (parts.size() == 1) return {parts[0], parts[0], parts[0]};
  if (parts.size() != 3) throw bad();
  return {parts[0], parts[1], parts[2]};
}

// --porosity P (sets `single`) or A:B with --axis; each in (0, 1).
std::optional<PorosityRamp> parse_porosity(const std::string& s, const std::string& axis,
                                           double& single) {
  const auto bad = [&] {
    return UsageError(fmt::format("--porosity: got '{}'; accepted: P or A:B (a ramp along "
                                  "--axis) with 0 < P, A, B < 1", s));
  };
  auto number = [&](const std::string& part) {
    char* end = nullptr;
    const double v = std::strtod(part.c_str(), &end);
    if (part.empty() || end != part.c_str() + part.size() || !(v > 0.0 && v < 1.0)) throw bad();
    return v;
  };
  const std::size_t colon = s.find(':');
  if (colon == std::string::npos) {
    single = number(s);
    return std::nullopt;
  }
  PorosityRamp r;
  r.from = number(s.substr(0, colon));
  r.to = number(s.substr(colon + 1));
  if (r.from == r.to) throw bad();
  if (axis == "x") r.axis = 0;
  else if (axis == "y") r.axis = 1;
  else if (axis == "z") r.axis = 2;
  else throw UsageError(fmt::format("--axis: got '{}'; accepted: x|y|z", axis));
  single = 0.5 * (r.from + r.to);
  return r;
}

std::filesystem::path default_cache() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return std::filesystem::path(xdg) / "cmcsurf";
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::filesystem::path(home) / ".cache" / "cmcsurf";
  return std::filesystem::temp_directory_path() / "cmcsurf-cache";
}

// FNV-1a of the run parameters' JSON: the cache key.
std::uint64_t parameters_hash(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
  return h;
}

// The member's field: from the cache when a finished entry has the same run parameters,
// otherwise computed (with progress) and stored there (field.vti, then member.json).
Field member_field(const ScaffoldCommand& cmd, const RunParams& p,
                   const std::filesystem::path& cache, nlohmann::json& about) {
  const nlohmann::json params = params_json(p);
  const std::string name = p.surface.rfind("expr:", 0) == 0 ? "expr" : p.surface;
  const std::filesystem::path dir =
      cache / fmt::format("{}-a{:.4f}-n{}-{:016x}", name, p.volume_fraction, p.grid,
                          parameters_hash(params.dump()));
  about = {{"cache", dir.string()}, {"parameters", params}};
  // One writer per entry: a second scaffold of the same member waits for the first and then
  // reuses its entry instead of computing it again (the cache is cmcsurf's own: forced).
  FolderClaim entry;
  try {
    entry = claim_output_folder(dir, {.kind = "cache", .option = "--cache", .force = true,
                                      .wait = true});
  } catch (const FolderRefused& e) {
    throw std::runtime_error(e.what());
  }
  if (std::filesystem::is_regular_file(dir / "member.json") &&
      std::filesystem::is_regular_file(dir / "field.vti")) {
    // A finished entry is reused only when its field file still has the CRC-32 it was
    // written with; a damaged or unreadable one is recomputed (and overwritten).
    std::string problem;
    try {
      const nlohmann::json saved = read_json_file(dir / "member.json");
      if (saved.value("parameters", nlohmann::json()) == params) {
        const auto crc = file_crc32(dir / "field.vti");
        const nlohmann::json want = saved.value("field_crc32", nlohmann::json());
        if (!crc) problem = "its field.vti cannot be read";
        else if (!want.is_number_unsigned()) problem = "its member.json has no field_crc32";
        else if (want.get<std::uint64_t>() != *crc) problem = "its field.vti fails its CRC-32";
        if (problem.empty()) {
          Field phi = load_phi(dir.string(), "--cache");
          about["reused"] = true;
          about["run"] = saved.value("run", nlohmann::json());
          if (!cmd.quiet) std::cerr << fmt::format("reusing the member in {}\n", dir.string());
          return phi;
        }
      }
    } catch (const std::exception& e) {
      problem = e.what();
    }
    if (!problem.empty() && !cmd.quiet)
      std::cerr << fmt::format("note: the cached member in {} is not reused ({}); recomputing\n",
                               dir.string(), problem);
  }
  if (!cmd.quiet)
    std::cerr << fmt::format("computing the member: surface {}, solid fraction {:g}, grid {} "
                             "(cached in {})\n", p.surface, p.volume_fraction, p.grid,
                             dir.string());
  Progress progress(cmd.quiet);
  RunResult r = run_cmc(p, RunContext([&](const StepRecord& s) { progress.step(s); }));
  progress.finish();
  const nlohmann::json run = run_report(p, r, apply_threads(0));
  ensure_directory(dir);
  std::filesystem::remove(dir / "member.json");  // the entry is unfinished until rewritten
  write_vti(dir / "field.vti", {{"phi", &r.phi}}, false, {{"surface", p.surface}});
  const auto crc = file_crc32(dir / "field.vti");
  if (!crc)
    throw std::runtime_error(fmt::format("cannot read back '{}'", (dir / "field.vti").string()));
  write_json_atomic(dir / "member.json",
                    {{"parameters", params}, {"run", run}, {"field_crc32", *crc}});
  about["reused"] = false;
  about["run"] = run;
  return std::move(r.phi);
}

// A member of another topology than its family's is not the lattice asked for.
void check_topology(const ScaffoldCommand& cmd, const nlohmann::json& about) {
  const auto t = member_topology(about.value("run", nlohmann::json()));
  if (!t) return;
  if (t->changed() && cmd.accept_topology_change) {
    if (!cmd.quiet)
      std::cerr << fmt::format("warning: the member's Euler characteristic {} is not its "
                               "family's {} (--accept-topology-change)\n", t->member, t->family);
    return;
  }
  check_member_topology(*t, fmt::format("--surface {} (member in {})", t->surface,
                                        about.value("cache", std::string())),
                        "--accept-topology-change");
}

// --target-modulus, --target-permeability, --pore-size, --min-wall as a problem: what solves
// what, checked before any work (exit 2). None when no target is given.
struct Targets {
  DesignProblem problem;
  DesignPlan plan;
  TargetValue modulus, permeability;
  bool graded() const { return modulus.ramp() || permeability.ramp(); }
};

std::optional<Targets> plan_targets(const ScaffoldCommand& cmd, const ScaffoldDesign& d) {
  Targets t;
  try {
    t.modulus = parse_target_value(cmd.target_modulus, "--target-modulus");
    t.permeability = parse_target_value(cmd.target_permeability, "--target-permeability");
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  if (!t.modulus.given() && !t.permeability.given() && std::isnan(cmd.pore_size) &&
      std::isnan(cmd.min_wall)) {
    if (cmd.strict_min_wall) throw UsageError("--strict-min-wall: only with --min-wall");
    if (cmd.porosity.empty())
      throw UsageError("--porosity: required (or --target-modulus or --target-permeability to "
                       "solve it)");
    return std::nullopt;
  }
  DesignProblem& p = t.problem;
  p.design = d;
  p.porosity_given = !cmd.porosity.empty();
  p.cell_size_given = cmd.cell_size_option->count() > 0;
  p.targets = {t.modulus.from, t.permeability.from, cmd.pore_size, cmd.min_wall,
               cmd.strict_min_wall};
  if (cmd.strict_min_wall && std::isnan(cmd.min_wall))
    throw UsageError("--strict-min-wall: only with --min-wall");
  try {
    set_properties_material(p.material, cmd.material);
    if (const std::string why = check_properties_request(p.material); !why.empty())
      throw std::invalid_argument(why);
    t.plan = plan_design(p);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  if (t.graded()) {
    const char* option = t.modulus.ramp() ? "--target-modulus" : "--target-permeability";
    if (!t.plan.solve_porosity ||
        (t.permeability.ramp() && t.plan.porosity_by != TargetQuantity::kPermeability))
      throw UsageError(fmt::format("{} A:B: grades the porosity it solves; a graded cell size "
                                   "(a permeability ramp at a given porosity) is not done",
                                   option));
    if (cmd.compare_nodal || cmd.properties || !cmd.shape.empty())
      throw UsageError(fmt::format("{} A:B: not with --compare-nodal, --properties or --shape "
                                   "(like --porosity A:B)", option));
  }
  return t;
}

// What a design solved and from which target, and each target recomputed on the part.
void print_design(const nlohmann::json& design, const std::string& units) {
  auto solved = [&](const nlohmann::json& rep) {
    std::string text;
    const auto& s = rep["solved"];
    if (s.contains("porosity"))
      text += fmt::format(" porosity {:.4f} ({})", s["porosity"].get<double>(),
                          rep["solved_by"]["porosity"].get<std::string>());
    if (s.contains("cell_size"))
      text += fmt::format(" cell size {:.4g} {} ({})", s["cell_size"].get<double>(), units,
                          rep["solved_by"]["cell_size"].get<std::string>());
    const std::size_t count = rep["evaluations"].size();
    return text + fmt::format(" from {} evaluation{}", count, count == 1 ? "" : "s");
  };
  std::string line = "design:";
  if (design.contains("ends"))
    line += " graded," + solved(design["ends"][0]) + "; to" + solved(design["ends"][1]);
  else if (design.contains("solved"))
    line += solved(design);
  if (design.contains("seconds"))
    line += fmt::format(" ({:.1f} s)", design["seconds"].get<double>());
  const auto& a = design["achieved"];
  for (const auto& [key, name, unit] :
       {std::tuple{"modulus_gpa", "modulus", std::string("GPa")},
        {"permeability_m2", "permeability", std::string("m^2")},
        {"pore_size", "mean pore size", units}})
    if (a.contains(key))
      line += fmt::format("; {} {:.4g} {} (target {:.4g}, {:+.1f} %)", name,
                          a[key]["value"].get<double>(), unit, a[key]["target"].get<double>(),
                          100.0 * a[key]["relative_error"].get<double>());
  if (a.contains("min_wall"))
    line += fmt::format("; thinnest wall (5th percentile) {:.4g} {} ({} --min-wall {})",
                        a["min_wall"]["wall_p5"].get<double>(), units,
                        a["min_wall"]["met"].get<bool>() ? "meets" : "BELOW",
                        a["min_wall"]["min_wall"].get<double>());
  std::cerr << line << "\n";
}

int run_scaffold(ScaffoldCommand& cmd) {
  // Everything is checked before anything is computed or written.
  try {
    std::vector<FileRole> reads;
    if (!cmd.shape.empty()) reads.push_back({cmd.shape, "--shape"});
    check_outputs_are_not_inputs(
        reads, {{cmd.out, "--out"}, {cmd.out + ".json", "--out's report (FILE.json)"},
                {cmd.out + ".html", "--out's page (FILE.html)"},
                {cmd.out + ".png", "--out's preview (FILE.png)"}});
  } catch (const OptionError& e) {
    throw UsageError(e.what());
  }
  cmd.params.surface = cmd.surface;
  ScaffoldDesign d;
  std::optional<PorosityRamp> ramp;
  if (!cmd.porosity.empty()) ramp = parse_porosity(cmd.porosity, cmd.axis, d.porosity);
  if (cmd.solid == "network") d.solid = SolidKind::kNetwork;
  else if (cmd.solid == "sheet") d.solid = SolidKind::kSheet;
  else throw UsageError(fmt::format("--solid: got '{}'; accepted: network|sheet", cmd.solid));
  if (cmd.graded_members != 0 && (cmd.graded_members < 2 || cmd.graded_members > 11))
    throw UsageError(
        fmt::format("--graded-members: got {}; accepted: 2 .. 11", cmd.graded_members));
  if (cmd.graded_members != 0 && d.solid == SolidKind::kSheet)
    throw UsageError("--graded-members: a graded sheet grades its wall around one member; only "
                     "for a network");
  if (cmd.compare_nodal && ramp)
    throw UsageError("--compare-nodal: takes one --porosity, not a ramp");
  // The unit cell's properties (docs/properties.md): the request checked before any work.
  PropertiesRequest properties_request;
  if (!cmd.material.empty() && !cmd.properties && cmd.target_modulus.empty())
    throw UsageError("--material: only with --properties or --target-modulus");
  if (cmd.properties) {
    if (ramp)
      throw UsageError("--properties: takes one --porosity, not a ramp (each member's cell "
                       "differs; `cmcsurf properties` computes any one of them)");
    try {
      set_properties_material(properties_request, cmd.material);
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
    if (const std::string why = check_properties_request(properties_request); !why.empty())
      throw UsageError(why);
  }
  if (!(cmd.cell_size >= kMinCellSize && cmd.cell_size <= kMaxCellSize))
    throw UsageError(fmt::format("--cell-size: got {}; accepted: {:g} .. {:g} (in --units; a "
                                 "smaller unit for smaller cells)",
                                 cmd.cell_size, kMinCellSize, kMaxCellSize));
  d.cell_size = cmd.cell_size;
  d.size = parse_size(cmd.size);
  std::optional<ShapeFill> shape;
  if (!cmd.shape.empty()) {
    if (cmd.size_option->count() > 0)
      throw UsageError("--size: not with --shape (the part is the shape's own bounding box)");
    if (ramp) throw UsageError("--shape: takes one --porosity, not a ramp");
    try {
      require_regular_file(cmd.shape, "--shape");  // a FIFO would block the open
    } catch (const std::runtime_error& e) {
      throw UsageError(e.what());
    }
    if (!std::filesystem::is_regular_file(cmd.shape))
      throw UsageError(fmt::format("--shape: '{}' is not a file", cmd.shape));
    shape.emplace();
    try {
      shape->mesh = read_stl(cmd.shape);
    } catch (const std::runtime_error& e) {
      throw UsageError(fmt::format("--shape: {}", e.what()));
    }
    const MeshStats s = analyze_mesh(shape->mesh);
    if (!s.closed() || !s.manifold() || !(std::abs(s.volume) > 0))
      throw UsageError(fmt::format(
          "--shape: '{}' is not a closed manifold solid ({} boundary edges, {} non-manifold "
          "edges); accepted: one closed, manifold triangle mesh in --units", cmd.shape,
          s.boundary_edges, s.nonmanifold_edges));
    for (int c = 0; c < 3; ++c) d.size[c] = s.max[c] - s.min[c];
    if (!(cmd.skin >= 0) || !std::isfinite(cmd.skin) ||
        cmd.skin > 0.5 * *std::min_element(d.size.begin(), d.size.end()))
      throw UsageError(fmt::format(
          "--skin: got {}; accepted: 0 .. half the shape's smallest extent, in --units", cmd.skin));
    shape->skin = cmd.skin;
  } else if (cmd.skin != 0.0) {
    throw UsageError("--skin: only with --shape");
  }
  if (!is_mesh_unit(cmd.units))
    throw UsageError(fmt::format("--units: got '{}'; accepted: {}", cmd.units, mesh_units_list()));
  d.units = cmd.units;
  d.keep_fragments = cmd.keep_fragments;
  if (cmd.max_triangles < 0 || cmd.max_triangles > kMaxTriangles)
    throw UsageError(fmt::format("--max-triangles: got {}; accepted: 1 .. {} (0: no budget)",
                                 cmd.max_triangles, kMaxTriangles));
  d.decimate.max_triangles = std::size_t(cmd.max_triangles);
  if (!(cmd.tolerance >= 0 && cmd.tolerance <= kMaxCellSize))
    throw UsageError(fmt::format("--tolerance: got {}; accepted: 0 .. {:g} in --units (0: none)",
                                 cmd.tolerance, kMaxCellSize));
  d.decimate.tolerance = cmd.tolerance;
  if (!(cmd.min_feature >= 0 && cmd.min_feature <= kMaxCellSize))
    throw UsageError(fmt::format("--min-feature: got {}; accepted: 0 .. {:g} in --units (0: "
                                 "none)", cmd.min_feature, kMaxCellSize));
  d.min_feature = cmd.min_feature;
  const nlohmann::json mesh_size = apply_mesh_size(cmd, d);
  std::optional<Targets> targets = plan_targets(cmd, d);
  cmd.params.volume_fraction = member_volume_fraction(d);
  finish_run_options(cmd.params, cmd.strings, true);
  if (ramp) ramp->fraction_tol = cmd.params.volume_tol;  // the members' own tolerance
  // The box in lattice nodes ("" when it fits); again after a design solves the cell size.
  auto box_problem = [&]() -> std::string {
    const double h = d.cell_size / cmd.params.grid;
    double nodes = 1.0;
    for (int c = 0; c < 3; ++c) {
      if (d.size[c] / h > 8192 || d.size[c] / h < 2)
        return fmt::format(
            "{}: {} {} is {:.0f} grid spacings (--cell-size / --grid = {:.4g}); accepted: 2 .. "
            "8192", shape ? "--shape" : "--size", d.size[c], d.units, d.size[c] / h, h);
      nodes *= std::ceil(d.size[c] / h);
    }
    if (nodes > kMaxPartNodes)
      return fmt::format(
          "{}: the box is {:.3g} lattice nodes at --cell-size / --grid = {:.4g} {}; accepted: "
          "at most {:.3g} (about 9 bytes each, plus the mesh): a smaller box or --grid",
          shape ? "--shape" : "--size", nodes, h, d.units, kMaxPartNodes);
    return {};
  };
  if (const std::string why = box_problem(); !why.empty()) throw UsageError(why);
  MeshPlan plan;
  plan.out = cmd.out;
  try {
    plan.format = mesh_output_format(cmd.format, plan.out);
  } catch (const OptionError& e) {
    throw UsageError(e.what());
  }
  plan.params.units = d.units;
  const std::filesystem::path cache =
      cmd.cache.empty() ? default_cache() : std::filesystem::path(cmd.cache);
  if (std::filesystem::exists(cache) && !std::filesystem::is_directory(cache))
    throw UsageError(fmt::format("--cache: '{}' exists and is not a directory", cache.string()));
  const int threads = apply_threads(cmd.threads);

  // Design from targets: the porosity (each end of a graded target) and the cell size solved.
  nlohmann::json design_report;
  auto member_at = [&](double porosity) {
    RunParams p = cmd.params;
    p.volume_fraction = d.solid == SolidKind::kNetwork ? 1.0 - porosity : 0.5;
    nlohmann::json about;
    Field f = member_field(cmd, p, cache, about);
    check_topology(cmd, about);
    return f;
  };
  if (targets && targets->plan.any()) {
    auto say = [&](const std::string& line) {
      if (!cmd.quiet) std::cerr << line << "\n";
    };
    try {
      if (targets->graded()) {
        std::vector<DesignSolution> ends;
        for (int end = 0; end < 2; ++end) {
          DesignProblem p = targets->problem;
          if (targets->modulus.ramp())
            p.targets.modulus_gpa = end == 0 ? targets->modulus.from : targets->modulus.to;
          else
            p.targets.permeability_m2 =
                end == 0 ? targets->permeability.from : targets->permeability.to;
          ends.push_back(solve_design(p, targets->plan, member_at, say));
        }
        ramp = parse_porosity(fmt::format("{:.6f}:{:.6f}", ends[0].porosity, ends[1].porosity),
                              cmd.axis, d.porosity);
        ramp->fraction_tol = cmd.params.volume_tol;
        design_report = {{"ends", {ends[0].report, ends[1].report}},
                         {"seconds", ends[0].report["seconds"].get<double>() +
                                         ends[1].report["seconds"].get<double>()}};
      } else {
        const DesignSolution s = solve_design(targets->problem, targets->plan, member_at, say);
        d.porosity = s.porosity;
        d.cell_size = s.cell_size;
        design_report = s.report;
      }
    } catch (const TargetUnreachable& e) {
      std::cerr << "error: " << e.what() << "\n";
      return kExitFailure;
    }
    cmd.params.volume_fraction = member_volume_fraction(d);
    if (const std::string why = box_problem(); !why.empty()) {
      std::cerr << fmt::format("error: the design's cell size {:.4g} {}: {}\n", d.cell_size,
                               d.units, why);
      return kExitFailure;
    }
  }

  const auto t0 = std::chrono::steady_clock::now();
  nlohmann::json member;
  Field phi;
  std::vector<GradedMember> members;
  if (ramp && d.solid == SolidKind::kNetwork) {
    // Members at evenly spaced solid fractions from one end of the ramp to the other.
    const double a0 = 1.0 - std::max(ramp->from, ramp->to),
                 a1 = 1.0 - std::min(ramp->from, ramp->to);
    const int count = cmd.graded_members > 0
                          ? cmd.graded_members
                          : std::max(2, int(std::ceil((a1 - a0) / 0.1 - 1e-9)) + 1);
    member = nlohmann::json::array();
    for (int m = 0; m < count; ++m) {
      RunParams p = cmd.params;
      p.volume_fraction = a0 + (a1 - a0) * m / (count - 1);
      nlohmann::json about;
      GradedMember g;
      g.phi = member_field(cmd, p, cache, about);
      check_topology(cmd, about);
      g.volume_fraction = about["run"].value("volume_fraction", p.volume_fraction);
      members.push_back(std::move(g));
      member.push_back(about);
    }
  } else {
    phi = member_field(cmd, cmd.params, cache, member);
    check_topology(cmd, member);
  }
  const double member_seconds =
      seconds_since(t0);
  ScaffoldPart part;
  try {
    // A graded sheet grades the wall around the one balanced member.
    const DecimateProgress progress = decimate_progress(cmd);
    const ShapeFill* fill = shape ? &*shape : nullptr;
    part = !ramp                          ? design_scaffold(phi, d, fill, progress)
           : d.solid == SolidKind::kSheet ? design_graded_sheet(phi, d, *ramp, progress)
                                          : design_graded_scaffold(members, d, *ramp, progress);
  } catch (const ClosedCellError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitFailure;
  } catch (const std::invalid_argument& e) {
    throw UsageError(fmt::format("--porosity: {}", e.what()));
  }
  if (shape) part.report["shape"]["file"] = cmd.shape;
  part.report["mesh_size"] = mesh_size;
  part.report["mesh_size"]["grid"] = cmd.params.grid;
  part.report["mesh_size"]["lattice_spacing"] = d.cell_size / cmd.params.grid;
  if (targets) {
    // The targets recomputed on the part as written (its cell, its morphometry).
    DesignProblem p = targets->problem;
    p.design.porosity = d.porosity;
    p.design.cell_size = d.cell_size;
    if (ramp) p.targets.modulus_gpa = p.targets.permeability_m2 = NAN;  // the ends' are above
    nlohmann::json achieved;
    try {
      achieved = confirm_design(p, phi, part.report, part.warnings);
    } catch (const TargetUnreachable& e) {
      std::cerr << "error: " << e.what() << "\n";
      return kExitFailure;
    }
    if (design_report.is_null()) design_report = nlohmann::json::object();
    design_report["achieved"] = achieved;
    part.report["design"].update(design_report);
    part.report["warnings"] = part.warnings;
  }
  if (cmd.compare_nodal) {
    if (!cmd.quiet) std::cerr << "building the nodal twin (--compare-nodal)\n";
    part.report["compare_nodal"] =
        compare_with_nodal(phi, cmd.params, d, part, shape ? &*shape : nullptr);
  }
  if (cmd.properties) {
    // The unit cell of the part as built: phase 1 of the member (a network) or the wall of
    // the part's solved thickness around its surface (a sheet).
    if (!cmd.quiet) std::cerr << "computing the unit cell's properties (--properties)\n";
    PropertiesRequest pr = properties_request;
    pr.cell_size = d.cell_size;
    pr.units = d.units;
    pr.surface = cmd.surface;
    pr.compare_nodal = cmd.compare_nodal;
    try {
      set_properties_solid(pr, cmd.solid, 1, NAN,
                           d.solid == SolidKind::kSheet
                               ? part.report["sheet"]["thickness"].get<double>()
                               : NAN);
      part.report["properties"] = compute_properties(phi, pr, [&](const std::string& line) {
        if (!cmd.quiet) std::cerr << "  " << line << "\n";
      });
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(fmt::format("--properties: {}", e.what()));
    }
  }
  const nlohmann::json& r = part.report;
  plan.meta.title = fmt::format("cmcsurf {} {} scaffold", cmd.surface, cmd.solid);
  plan.meta.description = fmt::format(
      "surface={}; solid={}; porosity={:.4f} (target {}); cell_size={} {}; size={}x{}x{} {}{}",
      cmd.surface, cmd.solid, r["porosity"].get<double>(),
      ramp ? fmt::format("{:.6g}:{:.6g} along {}", ramp->from, ramp->to, cmd.axis)
           : fmt::format("{:.6g}", d.porosity),
      d.cell_size, d.units,
      d.size[0], d.size[1], d.size[2], d.units,
      d.solid == SolidKind::kSheet
          ? fmt::format("; thickness={:.4g} {}", r["sheet"]["thickness"].get<double>(), d.units)
          : "");
  nlohmann::json members_about = {{"members", member}, {"seconds", member_seconds}};
  if (!ramp || d.solid == SolidKind::kSheet)
    members_about = member, members_about["seconds"] = member_seconds;
  std::optional<PartPageMeasures> page;
  if (!cmd.no_page) {
    page = measure_part_page(part.mesh);
    part.report["seconds"].update(part_page_seconds(*page));
  }
  write_mesh_with_report(part.mesh, part.report, plan,
                         {{"member", members_about}, {"threads", threads},
                          {"stl_bytes_equivalent", 84 + 50 * part.mesh.triangles.size()}});
  if (page) {
    // From FILE.json as written, so that the page shows the file's numbers.
    const double seconds =
        write_part_page(part_page_path(plan.out), part_preview_path(plan.out),
                        read_json_file(plan.out.string() + ".json"), *page);
    if (!cmd.quiet)
      std::cerr << fmt::format("wrote {} and {} in {:.2f} s\n",
                               part_page_path(plan.out).string(),
                               part_preview_path(plan.out).string(), seconds);
  }
  if (!cmd.quiet) {
    const auto& m = r["morphometry"];
    const auto& t = r["topology"];
    std::cerr << fmt::format(
        "{} {} scaffold, {}x{}x{} {}: porosity {:.4f} (target {}, error {:+.1e}){}\n"
        "{} triangles, {}, {}; {} fragments removed ({:.3g} {}^3); pores percolate x y z\n",
        cmd.surface, cmd.solid, d.size[0], d.size[1], d.size[2], d.units,
        r["porosity"].get<double>(),
        ramp ? fmt::format("{:.6g}:{:.6g} along {}, mean {:.6g}", ramp->from, ramp->to, cmd.axis,
                           0.5 * (ramp->from + ramp->to))
             : fmt::format("{:.6g}", d.porosity),
        r["porosity_error"].get<double>(),
        d.solid == SolidKind::kSheet ? fmt::format(", wall thickness {:.4g} {}",
                                                   r["sheet"]["thickness"].get<double>(), d.units)
                                     : "",
        r["triangles"].get<long>(), r["checks"]["closed"].get<bool>() ? "closed" : "OPEN",
        r["checks"]["manifold"].get<bool>() ? "manifold" : "NOT manifold",
        t["fragments_removed"].get<bool>() ? t["fragments"].get<long>() : 0,
        t["fragments_removed"].get<bool>() ? t["fragment_volume"].get<double>() : 0.0, d.units);
    if (m.contains("wall_thickness") && m.contains("pore_size"))
      std::cerr << fmt::format(
          "specific surface {:.4g} 1/{}; wall thickness mean {:.4g} min {:.4g} {}; pore size mean "
          "{:.4g} min {:.4g} {}\n",
          m["specific_surface"].get<double>(), d.units, m["wall_thickness"]["mean"].get<double>(),
          m["wall_thickness"]["min"].get<double>(), d.units, m["pore_size"]["mean"].get<double>(),
          m["pore_size"]["min"].get<double>(), d.units);
    if (m.contains("members")) {
      // A ramp: each member's cell, from the most porous to the densest.
      std::string line = fmt::format("specific surface {:.4g} 1/{}; wall thickness and pore size "
                                     "mean (min) per member, {}:",
                                     m["specific_surface"].get<double>(), d.units, d.units);
      for (auto it = m["members"].begin(); it != m["members"].end(); ++it)
        line += fmt::format("{} porosity {:.2f}: wall {:.3g} ({:.3g}), pore {:.3g} ({:.3g})",
                            it == m["members"].begin() ? "" : ";",
                            (*it)["porosity"].get<double>(),
                            (*it)["wall_thickness"]["mean"].get<double>(),
                            (*it)["wall_thickness"]["min"].get<double>(),
                            (*it)["pore_size"]["mean"].get<double>(),
                            (*it)["pore_size"]["min"].get<double>());
      std::cerr << line << "\n";
    }
    if (r.contains("graded")) {
      std::string line = "porosity per cell along " + cmd.axis + ":";
      for (const auto& b : r["graded"]["profile"])
        line += fmt::format(" {:.3f}", b["porosity_nodes"].get<double>());
      std::cerr << line << " (lattice nodes)\n";
    }
    if (r.contains("compare_nodal") && r["compare_nodal"]["nodal"].contains("error")) {
      std::cerr << "--compare-nodal: the nodal twin is not a valid part: "
                << r["compare_nodal"]["nodal"]["error"].get<std::string>() << "\n";
    } else if (r.contains("compare_nodal")) {
      const auto& c = r["compare_nodal"];
      std::cerr << fmt::format("{:<28} {:>12} {:>12}\n", "--compare-nodal", "CMC", "nodal");
      auto row = [&](const std::string& name, const nlohmann::json& a, const nlohmann::json& b) {
        std::cerr << fmt::format("{:<28} {:>12.5g} {:>12.5g}\n", name, a.get<double>(),
                                 b.get<double>());
      };
      row("porosity", c["cmc"]["porosity"], c["nodal"]["porosity"]);
      row("mean curvature std (1/" + d.units + ")", c["cmc"]["mean_curvature_std"],
          c["nodal"]["mean_curvature_std"]);
      row("specific surface (1/" + d.units + ")", c["cmc"]["specific_surface"],
          c["nodal"]["specific_surface"]);
      if (c["cmc"].contains("wall_thickness")) {
        row("wall thickness mean (" + d.units + ")", c["cmc"]["wall_thickness"]["mean"],
            c["nodal"]["wall_thickness"]["mean"]);
        row("wall thickness std (" + d.units + ")", c["cmc"]["wall_thickness"]["std"],
            c["nodal"]["wall_thickness"]["std"]);
        row("pore size std (" + d.units + ")", c["cmc"]["pore_size"]["std"],
            c["nodal"]["pore_size"]["std"]);
        // The thinnest wall and narrowest pore: where the CMC part's evenness shows.
        for (const auto& [key, name] : {std::pair{"wall_thickness", "wall thickness"},
                                        {"pore_size", "pore size"}})
          for (const char* stat : {"min", "p5"})
            if (c["cmc"][key].contains(stat))
              row(fmt::format("{} {} ({})", name, stat, d.units), c["cmc"][key][stat],
                  c["nodal"][key][stat]);
        if (c["cmc"].contains("throat"))
          row("throat min (" + d.units + ")", c["cmc"]["throat"], c["nodal"]["throat"]);
      }
      if (c["cmc"].contains("thickness"))
        row("sheet thickness (" + d.units + ")", c["cmc"]["thickness"], c["nodal"]["thickness"]);
    }
    if (r.contains("properties")) {
      // One line per solid: the CMC cell, then its nodal twins when compared.
      const auto& pj = r["properties"];
      auto line = [&](const std::string& name, const nlohmann::json& p) {
        auto m3 = [&](const char* key) {  // mean of x, y, z or of a tensor's diagonal
          const auto& v = p[key];
          return v[0].is_array() ? (v[0][0].get<double>() + v[1][1].get<double>() +
                                    v[2][2].get<double>()) / 3.0
                                 : (v[0].get<double>() + v[1].get<double>() +
                                    v[2].get<double>()) / 3.0;
        };
        std::string text = fmt::format("{:<13} rel. density {:.4f}", name,
                                       p["relative_density"].get<double>());
        if (p.contains("youngs_modulus"))
          text += fmt::format("; E/E_s {:.4g} (min {:.4g}, max {:.4g}), G/E_s {:.4g}, nu {:.3g}, "
                              "Zener {:.3g}, HS bulk {:.2f}",
                              m3("youngs_modulus"), p["youngs_modulus_min"].get<double>(),
                              p["youngs_modulus_max"].get<double>(), m3("shear_modulus"),
                              m3("poisson_ratio"), p["zener_ratio"].get<double>(),
                              p["fraction_of_bound"]["bulk_modulus"].get<double>());
        if (p.contains("youngs_modulus_gpa"))
          text += fmt::format(", E {:.4g} GPa", m3("youngs_modulus_gpa"));
        if (p.contains("conductivity_solid"))
          text += fmt::format("; k_solid/k_s {:.4g} (HS {:.2f}), k_pore {:.4g}",
                              m3("conductivity_solid"),
                              p["fraction_of_bound"]["conductivity_solid"].get<double>(),
                              m3("conductivity_pore"));
        std::cerr << text << "\n";
        for (const auto& w : p["warnings"])
          std::cerr << fmt::format("warning ({}): {}\n", name, w.get<std::string>());
      };
      std::cerr << fmt::format("unit cell properties (--properties, {:.1f} s; / the solid's E_s, "
                               "k_s; mean of x, y, z):\n",
                               pj["properties_seconds"].get<double>());
      line("CMC " + cmd.solid, pj);
      if (pj.contains("nodal")) line("nodal", pj["nodal"]);
      if (pj.contains("nodal_offset")) line("nodal offset", pj["nodal_offset"]);
    }
    if (r["design"].contains("achieved")) print_design(r["design"], d.units);
    if (r.contains("decimation")) {
      const auto& dm = r["decimation"];
      if (dm["applied"].get<bool>())
        std::cerr << fmt::format(
            "decimated {} -> {} triangles ({} -> {} bytes as binary STL; error {:.3g} {}, "
            "volume {:+.2e})\n",
            dm["triangles_before"].get<long>(), dm["triangles_after"].get<long>(),
            dm["stl_bytes_before"].get<long>(), dm["stl_bytes_after"].get<long>(),
            dm["error"].get<double>(), d.units, dm["volume_change"].get<double>());
      else
        std::cerr << fmt::format("not decimated ({} triangles): {}\n",
                                 dm["triangles_before"].get<long>(), dm["note"].get<std::string>());
    }
    std::cerr << fmt::format("wrote {} ({} bytes) and {}.json\n", plan.out.string(),
                             std::filesystem::file_size(plan.out), plan.out.string());
  }
  for (const std::string& w : part.warnings) std::cerr << "warning: " << w << "\n";
  return 0;
}

}  // namespace

CommandFn add_scaffold_command(CLI::App& root) {
  auto cmd = std::make_shared<ScaffoldCommand>();
  CLI::App* app = root.add_subcommand(
      "scaffold",
      "A printable scaffold from design targets: computes (or reuses from the cache) the CMC "
      "member, trims the lattice to the box, solves a sheet's wall thickness for the porosity, "
      "removes fragments, checks that the pores percolate, measures wall and pore sizes, and "
      "writes FILE with FILE.json\nExample: cmcsurf scaffold --surface G --porosity 0.7 --solid "
      "sheet --cell-size 2 --size 10x10x20 --units mm --grid 32 --fast --out part.3mf");
  app->add_option("--surface", cmd->surface,
                  "Surface family: P, D, G, ... (see `cmcsurf surfaces`)")
      ->capture_default_str();
  app->add_option("--porosity", cmd->porosity,
                  "Target porosity of the part: 1 - solid / box volume, in (0, 1); A:B ramps it "
                  "linearly from A to B along --axis (a network's members are blended, a "
                  "sheet's wall thickness graded); required unless "
                  "--target-modulus or --target-permeability solves it");
  app->add_option("--axis", cmd->axis, "Axis of a --porosity A:B ramp: x, y or z")
      ->capture_default_str();
  app->add_option("--graded-members", cmd->graded_members,
                  "Members a ramp blends (default: one per 0.1 of porosity, at least 2)");
  app->add_option("--solid", cmd->solid,
                  "network (the region on one side of the CMC surface at solid fraction 1 - "
                  "porosity) or sheet (a wall around the surface at solid fraction 1/2, its "
                  "thickness solved for the porosity)")
      ->capture_default_str();
  cmd->cell_size_option =
      app->add_option("--cell-size", cmd->cell_size, "Edge of one unit cell in --units")
          ->capture_default_str();
  cmd->size_option =
      app->add_option(
             "--size", cmd->size,
             "The part's box AxBxC (or A) in --units; any size, the lattice is trimmed and capped")
          ->capture_default_str();
  app->add_option("--shape", cmd->shape,
                  "Fill this closed STL mesh (in --units) instead of a box: the lattice is cut to "
                  "it and capped on its surface, the porosity holds over its volume");
  app->add_option("--skin", cmd->skin,
                  "With --shape: a dense skin of this thickness inside its surface, in --units");
  app->add_option("--units", cmd->units, std::string("Length unit: ") + mesh_units_list())
      ->capture_default_str();
  app->add_option("--format", cmd->format,
                  std::string("Mesh format: ") + mesh_format_list() + " (default: from --out)");
  app->add_option("--out", cmd->out, "Output mesh file (a report goes to FILE.json)")->required();
  app->add_option("--cache", cmd->cache,
                  "Folder of computed members, keyed by their run parameters (default: "
                  "$XDG_CACHE_HOME/cmcsurf or ~/.cache/cmcsurf)");
  app->add_flag("--keep-fragments", cmd->keep_fragments,
                "Keep the pieces the box cuts off the solid");
  app->add_option("--max-triangles", cmd->max_triangles,
                  "Decimate to at most this many triangles (quadric edge collapses keeping the "
                  "solid closed, manifold, one piece)");
  cmd->tolerance_option = app->add_option(
      "--tolerance", cmd->tolerance,
      fmt::format("Decimate as far as the surface moves at most this, in --units (default: "
                  "{:g} mm unless --max-triangles is given; 0: not decimated)",
                  kDefaultChordalToleranceMm));
  app->add_option("--min-feature", cmd->min_feature,
                  "Warn when the thinnest wall or narrowest pore is below this (the printer's "
                  "resolution), in --units");
  app->add_flag("--compare-nodal", cmd->compare_nodal,
                "Also build the same design from the nodal approximation at the member's volume "
                "fraction and report both side by side (curvature, wall and pore spread, "
                "specific surface) in FILE.json");
  app->add_flag("--properties", cmd->properties,
                "Also the unit cell's effective stiffness and conductivities (the part's "
                "network or sheet at its thickness; with --compare-nodal the nodal cell's too) "
                "in FILE.json's properties (docs/properties.md)");
  app->add_option("--material", cmd->material,
                  "With --properties: the solid's E_GPa[,nu] (nu 0.3 otherwise), moduli also "
                  "in GPa");
  app->add_flag("--accept-topology-change", cmd->accept_topology_change,
                "Use a member whose topology (Euler characteristic) differs from its family's "
                "(the nodal start's); refused by default");
  // Design from targets (docs/scaffolds.md, "Design from targets").
  app->add_option("--target-modulus", cmd->target_modulus,
                  "Solve the porosity (a network's member, a sheet's wall) for this Young's "
                  "modulus of the unit cell in GPa (mean of x, y, z; needs --material); A:B "
                  "grades it along --axis");
  app->add_option("--target-permeability", cmd->target_permeability,
                  "A permeability in m^2 (mean of x, y, z): solves the cell size when the "
                  "porosity is given or solved by --target-modulus, else the porosity; A:B "
                  "grades the porosity along --axis");
  app->add_option("--pore-size", cmd->pore_size,
                  "Solve the cell size for this mean pore diameter in --units at the porosity "
                  "asked (given or solved)");
  app->add_option("--min-wall", cmd->min_wall,
                  "Warn when the thinnest wall (5th percentile of the wall thickness) is below "
                  "this, in --units");
  app->add_flag("--strict-min-wall", cmd->strict_min_wall,
                "With --min-wall: refuse (exit 1, nothing written) instead of warning");
  add_run_options(*app, cmd->params, cmd->strings, false);
  cmd->grid_option = app->get_option("--grid");
  app->add_option("--resolution", cmd->resolution,
                  "Lattice spacing (the printer's voxel) in --units instead of --grid: the "
                  "member's grid is the smallest accepted one with --cell-size / N <= this");
  app->add_flag("--no-page", cmd->no_page,
                "Write no page (FILE.html: the part in 3D, slices, wall and pore distributions, "
                "the tables) and no preview (FILE.png)");
  add_threads_option(*app, cmd->threads);
  app->add_flag("--quiet", cmd->quiet, "No progress or summary output");
  return {app, [cmd]() -> int { return run_scaffold(*cmd); }};
}

}  // namespace cmcsurf::cli
