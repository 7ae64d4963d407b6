#include "mesh_options.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <vector>

#include "cli_common.h"
#include "io/atomic_file.h"
#include "io/json_file.h"
#include "io/vti.h"

namespace cmcsurf::cli {

namespace {

constexpr int kMaxTiles = 64;
constexpr int kMaxCellsPerAxis = 2048;

std::array<int, 3> parse_tiles(const std::string& s, int n) {
  const auto bad = [&] {
    return UsageError(fmt::format(
        "--tile: got '{}'; accepted: AxBxC or A with integers 1..{} and A*N <= {} (N = {})", s,
        kMaxTiles, kMaxCellsPerAxis, n));
  };
  std::vector<int> parts;
  std::size_t pos = 0;
  for (;;) {
    const std::size_t x = s.find('x', pos);
    const std::string part = s.substr(pos, x == std::string::npos ? std::string::npos : x - pos);
    if (part.empty() || part.size() > 3 || part.find_first_not_of("0123456789") != std::string::npos)
      throw bad();
    parts.push_back(std::stoi(part));
    if (x == std::string::npos) break;
    pos = x + 1;
  }
  if (parts.size() != 1 && parts.size() != 3) throw bad();
  const std::array<int, 3> t = parts.size() == 1 ? std::array<int, 3>{parts[0], parts[0], parts[0]}
                                                 : std::array<int, 3>{parts[0], parts[1], parts[2]};
  for (int c : t)
    if (c < 1 || c > kMaxTiles || c * n > kMaxCellsPerAxis) throw bad();
  return t;
}

}  // namespace

void add_mesh_output_options(CLI::App& app, MeshOptionStrings& s, bool with_sheet) {
  app.add_option("--tile", s.tile, "Unit cells along x, y, z: AxBxC (or A for AxAxA)")
      ->capture_default_str();
  app.add_option("--cell-size", s.cell_size, "Edge of one unit cell in output units")
      ->capture_default_str();
  app.add_option("--units", s.units, std::string("Length unit of the coordinates: ") + mesh_units_list())
      ->capture_default_str();
  app.add_option("--solid", s.solid,
                 with_sheet ? "surface (the phi = 1/2 interface), network (the region phi > 1/2, "
                              "capped at the box) or sheet (a wall of --thickness around the "
                              "interface)"
                            : "surface (the phi = 1/2 interface) or network (the region phi > "
                              "1/2, capped at the box)")
      ->capture_default_str();
  app.add_flag("--other-phase", s.other_phase, "Use phase 0 (phi < 1/2) instead of phase 1");
  if (with_sheet)
    app.add_option("--thickness", s.thickness, "Sheet wall thickness in output units");
  app.add_option("--format", s.format,
                 std::string("Mesh format: ") + mesh_format_list() + " (default: from --out)");
  app.add_option("--out", s.out, "Output mesh file (a report goes to FILE.json)")->required();
}

MeshPlan finish_mesh_output_options(const MeshOptionStrings& s, int n) {
  MeshPlan plan;
  ScaffoldParams& p = plan.params;
  p.tiles = parse_tiles(s.tile, n);
  if (!(s.cell_size > 0) || !std::isfinite(s.cell_size) || s.cell_size > 1e6)
    throw UsageError(fmt::format("--cell-size: got {}; accepted: > 0 and <= 1e6", s.cell_size));
  p.cell_size = s.cell_size;
  if (!is_mesh_unit(s.units))
    throw UsageError(fmt::format("--units: got '{}'; accepted: {}", s.units, mesh_units_list()));
  p.units = s.units;
  try {
    p.solid = parse_solid_kind(s.solid);
  } catch (const std::invalid_argument& e) {
    throw UsageError(fmt::format("--solid: {}", e.what()));
  }
  p.other_phase = s.other_phase;
  if (p.solid == SolidKind::kSheet) {
    const double lo = s.cell_size / n, hi = 0.5 * s.cell_size;
    if (!(s.thickness >= lo && s.thickness <= hi))
      throw UsageError(fmt::format(
          "--thickness: got {}; accepted for --solid sheet: {:.6g} .. {:.6g} {} (one grid "
          "spacing of the N = {} field to half the cell size)",
          s.thickness, lo, hi, s.units, n));
    if (s.other_phase)
      throw UsageError("--other-phase: a sheet is the same for both phases; use it with "
                       "--solid surface|network");
    p.thickness = s.thickness;
  } else if (s.thickness != 0.0) {
    throw UsageError("--thickness: only accepted with --solid sheet");
  }
  if (s.out.empty()) throw UsageError("--out: a file name is required");
  plan.out = s.out;
  std::string format = s.format;
  if (format.empty()) {
    format = plan.out.extension().string();
    if (!format.empty()) format = format.substr(1);
  }
  try {
    plan.format = parse_mesh_format(format);
  } catch (const std::invalid_argument& e) {
    throw UsageError(fmt::format("--format: {} (or give --out a .stl/.ply/.obj/.3mf name)", e.what()));
  }
  if (std::filesystem::is_directory(plan.out))
    throw UsageError(fmt::format("--out: '{}' is a directory; give a file name", s.out));
  return plan;
}

Field load_phi(const std::string& from, const std::string& option) {
  std::filesystem::path path(from);
  if (std::filesystem::is_directory(path)) path /= "field.vti";
  if (!std::filesystem::is_regular_file(path))
    throw UsageError(fmt::format("{}: '{}' is neither a run directory with field.vti nor a .vti file",
                                 option, from));
  VtiReadOptions options;
  options.ghost = 2;
  options.max_n = kMaxCellsPerAxis;  // refused before anything is allocated
  options.only = "phi";              // the phase field cmcsurf writes; no other array is read
  VtiData data = read_vti(path, options);
  return std::move(data.arrays.at("phi"));
}

void write_mesh_with_report(const TriMesh& mesh, nlohmann::json report, const MeshPlan& plan,
                            const nlohmann::json& extra) {
  const auto t0 = std::chrono::steady_clock::now();
  if (plan.out.has_parent_path()) ensure_directory(plan.out.parent_path());
  write_mesh(plan.out, plan.format, mesh, plan.params.units);
  report["file"] = plan.out.filename().string();
  report["format"] = mesh_format_extension(plan.format);
  report["write_seconds"] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  report["version"] = version_string();
  report.update(extra);
  write_json_atomic(plan.out.string() + ".json", report);
}

void write_run_surface_mesh(const std::filesystem::path& dir, const Field& phi,
                            const std::string& format) {
  MeshPlan plan;
  plan.format = parse_mesh_format(format);
  plan.out = dir / (std::string("surface.") + mesh_format_extension(plan.format));
  const Scaffold s = build_scaffold(phi, plan.params);
  write_mesh_with_report(s.mesh, s.report, plan,
                         {{"note", "untiled phi = 1/2 surface; coordinates in unit cells"}});
}

}  // namespace cmcsurf::cli
