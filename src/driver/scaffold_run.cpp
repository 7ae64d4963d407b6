#include "driver/scaffold_run.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <numbers>
#include <optional>

#include "common/wall_clock.h"
#include "common/atomic_file.h"
#include "io/file_checksum.h"
#include "io/file_identity.h"
#include "common/input_file.h"
#include "io/json_file.h"
#include "io/mesh_output.h"
#include "io/output_folder.h"
#include "io/pvti.h"
#include "io/run_report.h"
#include "io/vti.h"
#include "mesh/mesh_size.h"
#include "mesh/scaffold_part.h"
#include "mesh/shape.h"
#include "parallel/memory.h"
#include "pipeline/member_topology.h"
#include "report/part_page.h"
#include "pipeline/properties_stage.h"
#include "model/run_schema.h"
#include "pipeline/scaffold_compare.h"
#include "pipeline/scaffold_design.h"

namespace cmcsurf {

namespace {

// About 5 GB of lattice (value, label, mark) before the mesh.
constexpr double kMaxPartNodes = 5.4e8;
// The part's peak memory per lattice node, mostly its mesh before and during the decimation
// (about 250 bytes per undecimated triangle). Measured on G at porosity 0.7, `/usr/bin/time`
// peaks between 64^3 and 160^3 nodes: a sheet (two walls, 1.8 triangles a node) 345-440
// bytes a node, a network (0.95 a node) 224; plus about 150 MB that does not grow. A part
// whose estimate is over the memory available is refused before any work: the default part
// at --grid 128 (640^3 nodes, about 100 GB by this estimate) ran 600 s into its decimation
// at 24 GB before it was stopped.
constexpr double kPartBytesPerNodeSheet = 400.0;
constexpr double kPartBytesPerNodeNetwork = 225.0;
constexpr double kPartFixedBytes = 150e6;
// A triangle budget: more than a lattice of kMaxPartNodes could give is no budget.
constexpr long kMaxTriangles = 4'000'000'000L;

using O = ScaffoldOptions;

}  // namespace

const std::vector<ScaffoldOption>& scaffold_option_table() {
  static const std::vector<ScaffoldOption> table = {
      {"out", "--out", "Output mesh file (a report goes to FILE.json)", &O::out},
      {"surface", "--surface", "Surface family: P, D, G, ... (see `cmcsurf surfaces`)",
       &O::surface},
      {"porosity", "--porosity",
       "Target porosity of the part: 1 - solid / box volume, in (0, 1); A:B ramps it linearly "
       "from A to B along --axis or, in a --shape, by depth (--grade-by surface; a network's "
       "members are blended, a sheet's wall thickness graded); required unless "
       "--target-modulus or --target-permeability solves it",
       &O::porosity},
      {"axis", "--axis", "Axis of a ramp (--porosity, --cell-size, a target A:B): x, y or z",
       &O::axis},
      {"grade_by", "--grade-by",
       "How --porosity A:B runs: axis (A at the low end of --axis, B at the high end) or "
       "surface (with --shape: A at the shape's surface, inside its --skin, B at --grade-depth "
       "below it and deeper; a network or a sheet)",
       &O::grade_by},
      {"grade_depth", "--grade-depth",
       "With --grade-by surface: the depth in --units over which the porosity goes from A to "
       "B, > 0 and at most half the shape's smallest extent (default: one --cell-size)",
       &O::grade_depth},
      {"graded_members", "--graded-members",
       "Members a ramp blends (default: one per 0.1 of porosity, at least 2)",
       &O::graded_members},
      {"solid", "--solid",
       "network (the region on one side of the CMC surface at solid fraction 1 - porosity) or "
       "sheet (a wall around the surface at solid fraction 1/2, its thickness solved for the "
       "porosity)",
       &O::solid},
      {"cell_size", "--cell-size",
       "Edge of one unit cell in --units; A:B grades it along --axis (a network: the two cell "
       "sizes blended smoothly over the middle third of the part)",
       &O::cell_size},
      {"size", "--size",
       "The part's box AxBxC (or A) in --units; any size, the lattice is trimmed and capped",
       &O::size},
      {"shape", "--shape",
       "Fill this closed STL mesh (in --units) instead of a box: the lattice is cut to it and "
       "capped on its surface, the porosity holds over its volume",
       &O::shape},
      {"skin", "--skin",
       "With --shape: a dense skin of this thickness inside its surface, in --units", &O::skin},
      {"units", "--units", std::string("Length unit: ") + mesh_units_list(), &O::units},
      {"format", "--format",
       std::string("Mesh format: ") + mesh_format_list() + " (default: from --out)",
       &O::format},
      {"cache", "--cache",
       "Folder of computed members, keyed by their run parameters (default: "
       "$XDG_CACHE_HOME/cmcsurf or ~/.cache/cmcsurf)",
       &O::cache},
      {"keep_fragments", "--keep-fragments", "Keep the pieces the box cuts off the solid",
       &O::keep_fragments},
      {"max_triangles", "--max-triangles",
       "Decimate to at most this many triangles (quadric edge collapses keeping the solid "
       "closed, manifold, one piece)",
       &O::max_triangles},
      {"tolerance", "--tolerance",
       fmt::format("Decimate as far as the surface moves at most this, in --units (default: "
                   "{:g} mm unless --max-triangles is given; 0: not decimated)",
                   kDefaultChordalToleranceMm),
       &O::tolerance},
      {"resolution", "--resolution",
       "Lattice spacing (the printer's voxel) in --units instead of --grid: the member's grid "
       "is the smallest accepted one with --cell-size / N <= this",
       &O::resolution},
      {"min_feature", "--min-feature",
       "Warn when the thinnest wall or narrowest pore is below this (the printer's "
       "resolution), in --units",
       &O::min_feature},
      {"compare_nodal", "--compare-nodal",
       "Also build the same design from the nodal approximation at the member's volume "
       "fraction and report both side by side (curvature, wall and pore spread, specific "
       "surface) in FILE.json",
       &O::compare_nodal},
      {"properties", "--properties",
       "Also the unit cell's effective stiffness and conductivities (the part's network or "
       "sheet at its thickness; with --compare-nodal the nodal cell's too) in FILE.json's "
       "properties (docs/properties.md)",
       &O::properties},
      {"material", "--material",
       "With --properties: the solid's E_GPa[,nu] (nu 0.3 otherwise), moduli also in GPa",
       &O::material},
      {"accept_topology_change", "--accept-topology-change",
       "Use a member whose topology (Euler characteristic) differs from its family's (the "
       "nodal start's); refused by default",
       &O::accept_topology_change},
      {"target_modulus", "--target-modulus",
       "Solve the porosity (a network's member, a sheet's wall) for this Young's modulus of "
       "the unit cell in GPa (mean of x, y, z; needs --material); A:B grades it along --axis",
       &O::target_modulus},
      {"target_permeability", "--target-permeability",
       "A permeability in m^2 (mean of x, y, z): solves the cell size when the porosity is "
       "given or solved by --target-modulus, else the porosity; A:B grades the porosity along "
       "--axis",
       &O::target_permeability},
      {"pore_size", "--pore-size",
       "Solve the cell size for this mean pore diameter in --units at the porosity asked "
       "(given or solved)",
       &O::pore_size},
      {"min_wall", "--min-wall",
       "Warn when the thinnest wall (5th percentile of the wall thickness) is below this, in "
       "--units",
       &O::min_wall},
      {"strict_min_wall", "--strict-min-wall",
       "With --min-wall: refuse (exit 1, nothing written) instead of warning",
       &O::strict_min_wall},
      {"no_page", "--no-page",
       "Write no page (FILE.html: the part in 3D, slices, wall and pore distributions, the "
       "tables) and no preview (FILE.png)",
       &O::no_page},
  };
  return table;
}

const char* ScaffoldOption::type() const {
  return std::visit(
      [](auto m) -> const char* {
        using T = std::remove_reference_t<decltype(ScaffoldOptions{}.*m)>;
        if constexpr (std::is_same_v<T, std::string>) return "str";
        else if constexpr (std::is_same_v<T, double>) return "float";
        else if constexpr (std::is_same_v<T, bool>) return "bool";
        else return "int";
      },
      member);
}

void set_scaffold_option(ScaffoldOptions& o, const ScaffoldOption& option,
                         const nlohmann::json& v) {
  if (v.is_null()) return;
  const auto wrong = [&](const char* accepted) {
    return OptionError(fmt::format("{}: got {}; accepted: {}", option.cli, v.dump(), accepted));
  };
  std::visit(
      [&](auto m) {
        auto& x = o.*m;
        using T = std::remove_reference_t<decltype(x)>;
        if constexpr (std::is_same_v<T, std::string>) {
          if (!v.is_string()) throw wrong("a string");
          x = v.get<std::string>();
        } else if constexpr (std::is_same_v<T, bool>) {
          if (!v.is_boolean()) throw wrong("True or False");
          x = v.get<bool>();
        } else if constexpr (std::is_same_v<T, double>) {
          if (!v.is_number()) throw wrong("a number");
          x = v.get<double>();
        } else {
          if (!v.is_number_integer()) throw wrong("an integer");
          const auto big = v.get<long long>();
          if (big < std::numeric_limits<T>::min() || big > std::numeric_limits<T>::max())
            throw wrong("an integer in the option's range");
          x = T(big);
        }
      },
      option.member);
  o.given.insert(option.key);
}

void set_run_option_json(RunParams& p, RunChoices& c, const std::string& key,
                         const nlohmann::json& v) {
  const RunOption* o = find_run_option(key);
  if (o == nullptr) throw OptionError(fmt::format("unknown option '{}'", key));
  if (v.is_null()) return;  // --fast or --paper chooses
  const auto wrong = [&](const char* accepted) {
    return OptionError(fmt::format("{}: got {}; accepted: {}", o->name(), v.dump(), accepted));
  };
  std::visit(
      [&](const auto& ref) {
        using R = std::decay_t<decltype(ref)>;
        if constexpr (std::is_same_v<R, RunChoice>) {
          if (!v.is_string()) throw wrong("a string");
          c.text[key] = v.get<std::string>();
        } else {
          auto& x = ref(p);
          using T = std::decay_t<decltype(x)>;
          if constexpr (std::is_same_v<T, bool>) {
            if (!v.is_boolean()) throw wrong("True or False");
            x = v.get<bool>();
          } else if constexpr (std::is_same_v<T, double>) {
            if (!v.is_number()) throw wrong("a number");
            x = v.get<double>();
          } else if constexpr (std::is_same_v<T, std::string>) {
            if (!v.is_string()) throw wrong("a string");
            x = v.get<std::string>();
          } else {
            if (!v.is_number_integer()) throw wrong("an integer");
            if constexpr (std::is_same_v<T, std::uint64_t>) {
              if (v.is_number_unsigned()) x = v.get<std::uint64_t>();
              else if (v.get<long long>() < 0) throw wrong("an integer >= 0");
              else x = T(v.get<long long>());
            } else {
              const auto big = v.get<long long>();
              if (big < std::numeric_limits<T>::min() || big > std::numeric_limits<T>::max())
                throw wrong("an integer in the option's range");
              x = T(big);
            }
          }
        }
      },
      o->ref);
  c.given.insert(key);
}

nlohmann::json scaffold_option_schema() {
  const ScaffoldOptions defaults;
  nlohmann::json out = nlohmann::json::array();
  for (const ScaffoldOption& o : scaffold_option_table()) {
    nlohmann::json value;
    std::visit(
        [&](auto m) {
          const auto& x = defaults.*m;
          using T = std::remove_cvref_t<decltype(x)>;
          if constexpr (std::is_same_v<T, double>) {
            if (std::isfinite(x)) value = x;  // NaN: none
          } else {
            value = x;
          }
        },
        o.member);
    out.push_back({{"key", o.key}, {"cli", o.cli}, {"help", o.help}, {"type", o.type()},
                   {"default", value}});
  }
  return out;
}

namespace {

// Lines for the user, when someone listens.
void poll(const ScaffoldContext& ctx) {
  if (ctx.stop && ctx.stop()) throw ScaffoldInterrupted("scaffold: interrupted");
}

void say(const ScaffoldContext& ctx, const std::string& line) {
  poll(ctx);
  if (ctx.say) ctx.say(line);
}

// --resolution in place of --grid, and the default chordal tolerance when neither
// --tolerance nor --max-triangles is given. Returns FILE.json's `mesh_size`.
nlohmann::json apply_mesh_size(const ScaffoldOptions& o, bool grid_given, RunParams& params,
                               ScaffoldDesign& d) {
  nlohmann::json about;
  if (o.resolution != 0.0) {
    if (grid_given)
      throw OptionError("--resolution: not with --grid (each sets the lattice spacing)");
    if (!(o.resolution > 0 && o.resolution <= d.cell_size))
      throw OptionError(fmt::format("--resolution: got {}; accepted: 0 < R <= --cell-size "
                                    "({:g}) in --units", o.resolution, d.cell_size));
    try {
      params.grid = grid_for_resolution(d.cell_size, o.resolution, kMaxGrid);
    } catch (const std::invalid_argument& e) {
      throw OptionError(fmt::format("--resolution: {}", e.what()));
    }
    about["resolution"] = o.resolution;
  }
  const bool default_tolerance = o.given.count("tolerance") == 0 && o.max_triangles == 0;
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

// "AxBxC" or "A" in output units, each > 0.
Vec3 parse_size(const std::string& s) {
  const auto bad = [&] {
    return OptionError(fmt::format("--size: got '{}'; accepted: AxBxC or A, numbers {:g} .. "
                                   "{:g} in --units", s, kMinCellSize, kMaxCellSize));
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

int parse_axis(const std::string& axis);

// --cell-size S, or A:B graded along --axis; each in kMinCellSize .. kMaxCellSize.
std::optional<CellSizeRamp> parse_cell_size(const std::string& s, const std::string& axis,
                                            double& single) {
  const auto bad = [&] {
    return OptionError(fmt::format("--cell-size: got '{}'; accepted: S or A:B (graded along "
                                   "--axis), each {:g} .. {:g} (in --units; a smaller unit for "
                                   "smaller cells)", s, kMinCellSize, kMaxCellSize));
  };
  auto number = [&](const std::string& part) {
    char* end = nullptr;
    const double v = std::strtod(part.c_str(), &end);
    if (part.empty() || end != part.c_str() + part.size() ||
        !(v >= kMinCellSize && v <= kMaxCellSize))
      throw bad();
    return v;
  };
  const std::size_t colon = s.find(':');
  if (colon == std::string::npos) {
    single = number(s);
    return std::nullopt;
  }
  CellSizeRamp r;
  r.from = number(s.substr(0, colon));
  r.to = number(s.substr(colon + 1));
  if (r.from == r.to) throw bad();
  r.axis = parse_axis(axis);
  single = std::min(r.from, r.to);  // the lattice's spacing follows the finer cell
  return r;
}

int parse_axis(const std::string& axis) {
  if (axis == "x") return 0;
  if (axis == "y") return 1;
  if (axis == "z") return 2;
  throw OptionError(fmt::format("--axis: got '{}'; accepted: x|y|z", axis));
}

// --porosity P (sets `single`) or A:B with --axis; each in (0, 1).
std::optional<PorosityRamp> parse_porosity(const std::string& s, const std::string& axis,
                                           double& single) {
  const auto bad = [&] {
    return OptionError(fmt::format("--porosity: got '{}'; accepted: P or A:B (a ramp along "
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
  r.axis = parse_axis(axis);
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
Field member_field(const ScaffoldContext& ctx, const RunParams& p,
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
          VtiReadOptions read;
          read.ghost = 2;
          read.max_n = kMaxGrid;
          read.only = "phi";
          VtiData data = read_field_file(dir / "field.vti", read);
          about["reused"] = true;
          about["run"] = saved.value("run", nlohmann::json());
          say(ctx, fmt::format("reusing the member in {}", dir.string()));
          return std::move(data.arrays.at("phi"));
        }
      }
    } catch (const std::exception& e) {
      problem = e.what();
    }
    if (!problem.empty())
      say(ctx, fmt::format("note: the cached member in {} is not reused ({}); recomputing",
                           dir.string(), problem));
  }
  say(ctx, fmt::format("computing the member: surface {}, solid fraction {:g}, grid {} (cached "
                       "in {})", p.surface, p.volume_fraction, p.grid, dir.string()));
  RunContext run_context([&](const StepRecord& s) {
    if (ctx.step) ctx.step(s);
  });
  if (ctx.stop)
    run_context.control = [&] { return ctx.stop() ? RunControl::kStop : RunControl::kContinue; };
  RunResult r;
  try {
    r = run_cmc(p, run_context);
  } catch (const RunInterrupted&) {
    throw ScaffoldInterrupted("scaffold: interrupted while computing the member");
  }
  if (ctx.steps_done) ctx.steps_done();
  const nlohmann::json run = run_report(p, r, ctx.threads);
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
void check_topology(const ScaffoldOptions& o, const ScaffoldContext& ctx,
                    const nlohmann::json& about) {
  const auto t = member_topology(about.value("run", nlohmann::json()));
  if (!t) return;
  if (t->changed() && o.accept_topology_change) {
    say(ctx, fmt::format("warning: the member's Euler characteristic {} is not its family's {} "
                         "(--accept-topology-change)", t->member, t->family));
    return;
  }
  check_member_topology(*t, fmt::format("--surface {} (member in {})", t->surface,
                                        about.value("cache", std::string())),
                        "--accept-topology-change");
}

// --target-modulus, --target-permeability, --pore-size, --min-wall as a problem: what solves
// what, checked before any work. None when no target is given.
struct Targets {
  DesignProblem problem;
  DesignPlan plan;
  TargetValue modulus, permeability;
  bool graded() const { return modulus.ramp() || permeability.ramp(); }
};

std::optional<Targets> plan_targets(const ScaffoldOptions& o, const ScaffoldDesign& d) {
  Targets t;
  try {
    t.modulus = parse_target_value(o.target_modulus, "--target-modulus");
    t.permeability = parse_target_value(o.target_permeability, "--target-permeability");
  } catch (const std::invalid_argument& e) {
    throw OptionError(e.what());
  }
  if (!t.modulus.given() && !t.permeability.given() && std::isnan(o.pore_size) &&
      std::isnan(o.min_wall)) {
    if (o.strict_min_wall) throw OptionError("--strict-min-wall: only with --min-wall");
    if (o.porosity.empty())
      throw OptionError("--porosity: required (or --target-modulus or --target-permeability "
                        "to solve it)");
    return std::nullopt;
  }
  DesignProblem& p = t.problem;
  p.design = d;
  p.porosity_given = !o.porosity.empty();
  p.cell_size_given = o.given.count("cell_size") > 0;
  p.targets = {t.modulus.from, t.permeability.from, o.pore_size, o.min_wall,
               o.strict_min_wall};
  if (o.strict_min_wall && std::isnan(o.min_wall))
    throw OptionError("--strict-min-wall: only with --min-wall");
  try {
    set_properties_material(p.material, o.material);
    if (const std::string why = check_properties_request(p.material); !why.empty())
      throw std::invalid_argument(why);
    t.plan = plan_design(p);
  } catch (const std::invalid_argument& e) {
    throw OptionError(e.what());
  }
  if (t.graded()) {
    const char* option = t.modulus.ramp() ? "--target-modulus" : "--target-permeability";
    if (!t.plan.solve_porosity ||
        (t.permeability.ramp() && t.plan.porosity_by != TargetQuantity::kPermeability))
      throw OptionError(fmt::format("{} A:B: grades the porosity it solves; a graded cell size "
                                    "(a permeability ramp at a given porosity) is not done",
                                    option));
    if (o.compare_nodal || o.properties || !o.shape.empty())
      throw OptionError(fmt::format("{} A:B: not with --compare-nodal, --properties or --shape "
                                    "(like --porosity A:B)", option));
  }
  return t;
}

// The shape to fill (--shape, --skin), read and checked; sets d.size to its extent.
std::optional<ShapeFill> read_shape(const ScaffoldOptions& o, ScaffoldDesign& d) {
  if (o.shape.empty()) {
    if (o.skin != 0.0) throw OptionError("--skin: only with --shape");
    return std::nullopt;
  }
  if (o.given.count("size") > 0)
    throw OptionError("--size: not with --shape (the part is the shape's own bounding box)");
  try {
    require_regular_file(o.shape, "--shape");  // a FIFO would block the open
  } catch (const std::runtime_error& e) {
    throw OptionError(e.what());
  }
  if (!std::filesystem::is_regular_file(o.shape))
    throw OptionError(fmt::format("--shape: '{}' is not a file", o.shape));
  std::optional<ShapeFill> shape;
  shape.emplace();
  try {
    shape->mesh = read_stl(o.shape);
  } catch (const std::runtime_error& e) {
    throw OptionError(fmt::format("--shape: {}", e.what()));
  }
  const MeshStats s = analyze_mesh(shape->mesh);
  if (!s.closed() || !s.manifold() || !(std::abs(s.volume) > 0))
    throw OptionError(fmt::format(
        "--shape: '{}' is not a closed manifold solid ({} boundary edges, {} non-manifold "
        "edges); accepted: one closed, manifold triangle mesh in --units", o.shape,
        s.boundary_edges, s.nonmanifold_edges));
  for (int c = 0; c < 3; ++c) d.size[c] = s.max[c] - s.min[c];
  if (!(o.skin >= 0) || !std::isfinite(o.skin) ||
      o.skin > 0.5 * *std::min_element(d.size.begin(), d.size.end()))
    throw OptionError(fmt::format(
        "--skin: got {}; accepted: 0 .. half the shape's smallest extent, in --units", o.skin));
  shape->skin = o.skin;
  return shape;
}

// --grade-by and --grade-depth against the ramp and the shape; sets the ramp's depth.
void check_grading(const ScaffoldOptions& o, std::optional<PorosityRamp>& ramp,
                   const std::optional<ShapeFill>& shape, const ScaffoldDesign& d) {
  if (o.grade_by != "axis" && o.grade_by != "surface")
    throw OptionError(fmt::format("--grade-by: got '{}'; accepted: axis|surface", o.grade_by));
  if (o.grade_by == "axis") {
    if (o.given.count("grade_depth") > 0)
      throw OptionError("--grade-depth: only with --grade-by surface");
    return;
  }
  // By depth: a porosity ramp in a shape; what grades along an axis cannot run by depth.
  const char* other = !shape                                   ? "without --shape"
                      : !ramp                                  ? "without --porosity A:B"
                      : o.given.count("axis") > 0              ? "with --axis"
                      : o.cell_size.find(':') != std::string::npos ? "with --cell-size A:B"
                      : !o.target_modulus.empty() || !o.target_permeability.empty()
                          ? "with --target-modulus or --target-permeability"
                          : nullptr;
  if (other != nullptr)
    throw OptionError(fmt::format("--grade-by surface: not {} (accepted: --shape with "
                                  "--porosity A:B, A at its surface and B at --grade-depth)",
                                  other));
  const double smallest = *std::min_element(d.size.begin(), d.size.end());
  const double depth = o.grade_depth == 0.0 ? d.cell_size : o.grade_depth;
  if (!(depth > 0.0 && depth <= 0.5 * smallest))
    throw OptionError(fmt::format("--grade-depth: got {}; accepted: 0 < D <= {:g} (half the "
                                  "shape's smallest extent) in --units; 0: one --cell-size",
                                  depth, 0.5 * smallest));
  ramp->by_surface = true;
  ramp->depth = depth;
}

}  // namespace

ScaffoldRun make_scaffold(const ScaffoldOptions& o, RunParams params, const RunChoices& choices,
                          const ScaffoldContext& ctx) {
  // Everything is checked before anything is computed or written.
  if (o.out.empty()) throw OptionError("--out: required (the mesh file to write)");
  {
    std::vector<FileRole> reads;
    if (!o.shape.empty()) reads.push_back({o.shape, "--shape"});
    check_outputs_are_not_inputs(
        reads, {{o.out, "--out"}, {o.out + ".json", "--out's report (FILE.json)"},
                {o.out + ".html", "--out's page (FILE.html)"},
                {o.out + ".png", "--out's preview (FILE.png)"}});
  }
  params.surface = o.surface;
  ScaffoldDesign d;
  std::optional<PorosityRamp> ramp;
  if (!o.porosity.empty()) ramp = parse_porosity(o.porosity, o.axis, d.porosity);
  if (o.solid == "network") d.solid = SolidKind::kNetwork;
  else if (o.solid == "sheet") d.solid = SolidKind::kSheet;
  else throw OptionError(fmt::format("--solid: got '{}'; accepted: network|sheet", o.solid));
  if (o.graded_members != 0 && (o.graded_members < 2 || o.graded_members > 11))
    throw OptionError(
        fmt::format("--graded-members: got {}; accepted: 2 .. 11", o.graded_members));
  if (o.graded_members != 0 && d.solid == SolidKind::kSheet)
    throw OptionError("--graded-members: a graded sheet grades its wall around one member; "
                      "only for a network");
  if (o.compare_nodal && ramp) throw OptionError("--compare-nodal: takes one --porosity, not a "
                                                 "ramp");
  // The unit cell's properties (docs/properties.md): the request checked before any work.
  PropertiesRequest properties_request;
  if (!o.material.empty() && !o.properties && o.target_modulus.empty())
    throw OptionError("--material: only with --properties or --target-modulus");
  if (o.properties) {
    if (ramp)
      throw OptionError("--properties: takes one --porosity, not a ramp (each member's cell "
                        "differs; `cmcsurf properties` computes any one of them)");
    try {
      set_properties_material(properties_request, o.material);
    } catch (const std::invalid_argument& e) {
      throw OptionError(e.what());
    }
    if (const std::string why = check_properties_request(properties_request); !why.empty())
      throw OptionError(why);
  }
  const std::optional<CellSizeRamp> cell_ramp = parse_cell_size(o.cell_size, o.axis, d.cell_size);
  if (cell_ramp) {
    // Two cells of one member: a network at one porosity, built and measured as such.
    const char* other = ramp                    ? "--porosity A:B"
                        : d.solid != SolidKind::kNetwork ? "--solid sheet"
                        : !o.shape.empty()      ? "--shape"
                        : o.compare_nodal       ? "--compare-nodal"
                        : o.properties          ? "--properties"
                        : !o.target_modulus.empty() || !o.target_permeability.empty() ||
                                  !std::isnan(o.pore_size) || !std::isnan(o.min_wall)
                            ? "a design target"
                            : nullptr;
    if (other != nullptr)
      throw OptionError(fmt::format("--cell-size A:B: not with {} (a graded cell size is done "
                                    "for a network at one --porosity in a box)", other));
  }
  d.size = parse_size(o.size);
  std::optional<ShapeFill> shape = read_shape(o, d);
  check_grading(o, ramp, shape, d);
  if (!is_mesh_unit(o.units))
    throw OptionError(fmt::format("--units: got '{}'; accepted: {}", o.units, mesh_units_list()));
  d.units = o.units;
  d.keep_fragments = o.keep_fragments;
  if (o.max_triangles < 0 || o.max_triangles > kMaxTriangles)
    throw OptionError(fmt::format("--max-triangles: got {}; accepted: 1 .. {} (0: no budget)",
                                  o.max_triangles, kMaxTriangles));
  d.decimate.max_triangles = std::size_t(o.max_triangles);
  if (!(o.tolerance >= 0 && o.tolerance <= kMaxCellSize))
    throw OptionError(fmt::format("--tolerance: got {}; accepted: 0 .. {:g} in --units (0: "
                                  "none)", o.tolerance, kMaxCellSize));
  d.decimate.tolerance = o.tolerance;
  if (!(o.min_feature >= 0 && o.min_feature <= kMaxCellSize))
    throw OptionError(fmt::format("--min-feature: got {}; accepted: 0 .. {:g} in --units (0: "
                                  "none)", o.min_feature, kMaxCellSize));
  d.min_feature = o.min_feature;
  const nlohmann::json mesh_size = apply_mesh_size(o, choices.given.count("grid") > 0, params, d);
  const bool default_grid =
      !params.paper && o.resolution == 0.0 && choices.given.count("grid") == 0;
  if (default_grid) params.grid = kScaffoldGrid;
  std::optional<Targets> targets = plan_targets(o, d);
  params.volume_fraction = member_volume_fraction(d);
  {
    RunChoices c = choices;
    if (o.resolution != 0.0 || default_grid) c.given.insert("grid");  // --fast keeps it
    finish_run_params(params, c, true);
  }
  if (ramp) ramp->fraction_tol = params.volume_tol;  // the members' own tolerance
  // The box in lattice nodes ("" when it fits); again after a design solves the cell size.
  auto box_problem = [&]() -> std::string {
    const double h = d.cell_size / params.grid;
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
    const bool sheet = d.solid == SolidKind::kSheet;
    const double need =
        kPartFixedBytes + nodes * (sheet ? kPartBytesPerNodeSheet : kPartBytesPerNodeNetwork);
    const MemoryHeadroom room = memory_headroom();
    if (need > double(room.bytes))
      return fmt::format(
          "{}: the part is {:.3g} lattice nodes at --cell-size / --grid = {:.4g} {} and its "
          "mesh needs about {} of memory (about {:.0f} bytes a node for a {}), but {} is "
          "available ({}); accepted: a part that fits: a smaller box, a coarser --grid or a "
          "larger --resolution",
          shape ? "--shape" : "--size", nodes, h, d.units, format_bytes(std::uint64_t(need)),
          sheet ? kPartBytesPerNodeSheet : kPartBytesPerNodeNetwork,
          sheet ? "sheet" : "network", format_bytes(room.bytes), room.source);
    return {};
  };
  if (const std::string why = box_problem(); !why.empty()) throw OptionError(why);
  MeshPlan plan;
  plan.out = o.out;
  plan.format = mesh_output_format(o.format, plan.out);
  plan.params.units = d.units;
  const std::filesystem::path cache =
      o.cache.empty() ? default_cache() : std::filesystem::path(o.cache);
  if (std::filesystem::exists(cache) && !std::filesystem::is_directory(cache))
    throw OptionError(fmt::format("--cache: '{}' exists and is not a directory", cache.string()));

  // Design from targets: the porosity (each end of a graded target) and the cell size solved.
  nlohmann::json design_report;
  auto member_at = [&](double porosity) {
    RunParams p = params;
    p.volume_fraction = d.solid == SolidKind::kNetwork ? 1.0 - porosity : 0.5;
    nlohmann::json about;
    Field f = member_field(ctx, p, cache, about);
    check_topology(o, ctx, about);
    return f;
  };
  if (targets && targets->plan.any()) {
    auto progress = [&](const std::string& line) { say(ctx, line); };
    if (targets->graded()) {
      std::vector<DesignSolution> ends;
      for (int end = 0; end < 2; ++end) {
        DesignProblem p = targets->problem;
        if (targets->modulus.ramp())
          p.targets.modulus_gpa = end == 0 ? targets->modulus.from : targets->modulus.to;
        else
          p.targets.permeability_m2 =
              end == 0 ? targets->permeability.from : targets->permeability.to;
        ends.push_back(solve_design(p, targets->plan, member_at, progress));
      }
      ramp = parse_porosity(fmt::format("{:.6f}:{:.6f}", ends[0].porosity, ends[1].porosity),
                            o.axis, d.porosity);
      ramp->fraction_tol = params.volume_tol;
      design_report = {{"ends", {ends[0].report, ends[1].report}},
                       {"seconds", ends[0].report["seconds"].get<double>() +
                                       ends[1].report["seconds"].get<double>()}};
    } else {
      const DesignSolution s = solve_design(targets->problem, targets->plan, member_at, progress);
      d.porosity = s.porosity;
      d.cell_size = s.cell_size;
      design_report = s.report;
    }
    params.volume_fraction = member_volume_fraction(d);
    if (const std::string why = box_problem(); !why.empty())
      throw ScaffoldFailed(fmt::format("the design's cell size {:.4g} {}: {}", d.cell_size,
                                       d.units, why));
  }

  const auto t0 = std::chrono::steady_clock::now();
  nlohmann::json member;
  Field phi;
  std::vector<GradedMember> members;
  if (ramp && d.solid == SolidKind::kNetwork) {
    // Members at evenly spaced solid fractions from one end of the ramp to the other.
    const double a0 = 1.0 - std::max(ramp->from, ramp->to),
                 a1 = 1.0 - std::min(ramp->from, ramp->to);
    const int count = o.graded_members > 0
                          ? o.graded_members
                          : std::max(2, int(std::ceil((a1 - a0) / 0.1 - 1e-9)) + 1);
    member = nlohmann::json::array();
    for (int m = 0; m < count; ++m) {
      RunParams p = params;
      p.volume_fraction = a0 + (a1 - a0) * m / (count - 1);
      nlohmann::json about;
      GradedMember g;
      g.phi = member_field(ctx, p, cache, about);
      check_topology(o, ctx, about);
      g.volume_fraction = about["run"].value("volume_fraction", p.volume_fraction);
      members.push_back(std::move(g));
      member.push_back(about);
    }
  } else {
    phi = member_field(ctx, params, cache, member);
    check_topology(o, ctx, member);
  }
  const double member_seconds = seconds_since(t0);
  ScaffoldPart part;
  // The decimation's progress also polls for a stop (it is the longest stage after the solve).
  const DecimateProgress decimate = [&ctx](DecimateStage stage, int attempt, std::size_t left) {
    poll(ctx);
    if (ctx.decimate) ctx.decimate(stage, attempt, left);
  };
  poll(ctx);
  try {
    // A graded sheet grades the wall around the one balanced member.
    const ShapeFill* fill = shape ? &*shape : nullptr;
    part = cell_ramp ? design_graded_cell_scaffold(phi, d, *cell_ramp, decimate)
           : !ramp   ? design_scaffold(phi, d, fill, decimate)
           : d.solid == SolidKind::kSheet
               ? design_graded_sheet(phi, d, *ramp, decimate, fill)
               : design_graded_scaffold(members, d, *ramp, decimate, fill);
  } catch (const std::invalid_argument& e) {
    throw OptionError(fmt::format("--porosity: {}", e.what()));
  }
  if (shape) part.report["shape"]["file"] = o.shape;
  part.report["mesh_size"] = mesh_size;
  part.report["mesh_size"]["grid"] = params.grid;
  part.report["mesh_size"]["lattice_spacing"] = d.cell_size / params.grid;
  if (targets) {
    // The targets recomputed on the part as written (its cell, its morphometry).
    DesignProblem p = targets->problem;
    p.design.porosity = d.porosity;
    p.design.cell_size = d.cell_size;
    if (ramp) p.targets.modulus_gpa = p.targets.permeability_m2 = NAN;  // the ends' are above
    const nlohmann::json achieved = confirm_design(p, phi, part.report, part.warnings);
    if (design_report.is_null()) design_report = nlohmann::json::object();
    design_report["achieved"] = achieved;
    part.report["design"].update(design_report);
    part.report["warnings"] = part.warnings;
  }
  if (o.compare_nodal) {
    say(ctx, "building the nodal twin (--compare-nodal)");
    part.report["compare_nodal"] =
        compare_with_nodal(phi, params, d, part, shape ? &*shape : nullptr);
  }
  if (o.properties) {
    // The unit cell of the part as built: phase 1 of the member (a network) or the wall of
    // the part's solved thickness around its surface (a sheet).
    say(ctx, "computing the unit cell's properties (--properties)");
    PropertiesRequest pr = properties_request;
    pr.cell_size = d.cell_size;
    pr.units = d.units;
    pr.surface = o.surface;
    pr.compare_nodal = o.compare_nodal;
    try {
      set_properties_solid(pr, o.solid, 1, NAN,
                           d.solid == SolidKind::kSheet
                               ? part.report["sheet"]["thickness"].get<double>()
                               : NAN);
      part.report["properties"] = compute_properties(
          phi, pr, [&](const std::string& line) { say(ctx, "  " + line); });
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(fmt::format("--properties: {}", e.what()));
    }
  }
  const nlohmann::json& r = part.report;
  plan.meta.title = fmt::format("cmcsurf {} {} scaffold", o.surface, o.solid);
  plan.meta.description = fmt::format(
      "surface={}; solid={}; porosity={:.4f} (target {}); cell_size={} {}; size={}x{}x{} {}{}",
      o.surface, o.solid, r["porosity"].get<double>(),
      ramp ? fmt::format("{:.6g}:{:.6g} {}", ramp->from, ramp->to,
                         ramp->by_surface
                             ? fmt::format("from the surface over {:g} {}", ramp->depth, d.units)
                             : "along " + o.axis)
           : fmt::format("{:.6g}", d.porosity),
      cell_ramp ? fmt::format("{:g}:{:g} along {}", cell_ramp->from, cell_ramp->to, o.axis)
                : fmt::format("{:g}", d.cell_size),
      d.units, d.size[0], d.size[1], d.size[2], d.units,
      d.solid == SolidKind::kSheet
          ? fmt::format("; thickness={:.4g} {}", r["sheet"]["thickness"].get<double>(), d.units)
          : "");
  nlohmann::json members_about = {{"members", member}, {"seconds", member_seconds}};
  if (!ramp || d.solid == SolidKind::kSheet)
    members_about = member, members_about["seconds"] = member_seconds;
  poll(ctx);
  std::optional<PartPageMeasures> page;
  if (!o.no_page) {
    page = measure_part_page(part.mesh);
    part.report["seconds"].update(part_page_seconds(*page));
  }
  write_mesh_with_report(part.mesh, part.report, plan,
                         {{"member", members_about}, {"threads", ctx.threads},
                          {"stl_bytes_equivalent", 84 + 50 * part.mesh.triangles.size()}});
  ScaffoldRun run;
  run.out = plan.out;
  run.report = read_json_file(plan.out.string() + ".json");
  run.warnings = part.warnings;
  if (page) {
    // From FILE.json as written, so that the page shows the file's numbers.
    run.page = part_page_path(plan.out);
    run.preview = part_preview_path(plan.out);
    run.page_seconds = write_part_page(run.page, run.preview, run.report, *page);
  }
  return run;
}

nlohmann::json cell_morphometry(const Field& phi, const std::string& solid, double porosity,
                                double thickness, double cell_size, const std::string& units) {
  if (!(cell_size >= kMinCellSize && cell_size <= kMaxCellSize))
    throw OptionError(fmt::format("cell_size: got {}; accepted: {:g} .. {:g} (in units)",
                                  cell_size, kMinCellSize, kMaxCellSize));
  if (!is_mesh_unit(units))
    throw OptionError(fmt::format("units: got '{}'; accepted: {}", units, mesh_units_list()));
  ScaffoldDesign d;
  d.cell_size = cell_size;
  d.units = units;
  if (solid == "network") {
    if (!std::isnan(porosity) || !std::isnan(thickness))
      throw OptionError("porosity, thickness: only for a sheet (a network's solid is the run's "
                        "own, at its solid fraction)");
    d.solid = SolidKind::kNetwork;
  } else if (solid == "sheet") {
    d.solid = SolidKind::kSheet;
    if (std::isnan(porosity) == std::isnan(thickness))
      throw OptionError("porosity, thickness: a sheet takes one of them");
    if (!std::isnan(thickness)) {
      // Steiner's formula per cell, A t + (pi chi / 6) t^3, for the sheet's solid fraction.
      if (!(thickness > 0.0 && thickness < 0.5 * cell_size))
        throw OptionError(fmt::format("thickness: got {}; accepted: 0 < T < cell_size / 2 ({:g})",
                                      thickness, 0.5 * cell_size));
      const nlohmann::json s = periodic_surface_json(phi);
      const double t = thickness / cell_size, area = s["area"].get<double>(),
                   chi = s["euler_characteristic"].get<double>();
      porosity = 1.0 - (area * t + std::numbers::pi * chi / 6 * t * t * t);
    }
    if (!(porosity > 0.0 && porosity < 1.0))
      throw OptionError(fmt::format("porosity: got {}; accepted: 0 < P < 1", porosity));
    d.porosity = porosity;
  } else {
    throw OptionError(fmt::format("solid: got '{}'; accepted: network|sheet", solid));
  }
  nlohmann::json m;
  try {
    m = design_cell_morphometry(phi, d);
  } catch (const std::invalid_argument& e) {
    throw OptionError(e.what());
  }
  m["solid"] = solid;
  m["cell_size"] = cell_size;
  m["units"] = units;
  if (d.solid == SolidKind::kSheet) m["porosity"] = porosity;
  return m;
}

}  // namespace cmcsurf
