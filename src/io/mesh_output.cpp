#include "io/mesh_output.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <vector>

#include "common/wall_clock.h"
#include "common/atomic_file.h"
#include "io/json_file.h"
#include "model/run_options.h"

namespace cmcsurf {

namespace {

constexpr int kMaxTiles = 64;
constexpr int kMaxCellsPerAxis = 2048;

std::array<int, 3> parse_tiles(const std::string& s, int n) {
  const auto bad = [&] {
    return OptionError(fmt::format(
        "--tile: got '{}'; accepted: AxBxC or A with integers 1..{} and A*N <= {} (N = {})", s,
        kMaxTiles, kMaxCellsPerAxis, n));
  };
  std::vector<int> parts;
  std::size_t pos = 0;
  for (;;) {
    const std::size_t x = s.find('x', pos);
    const std::string part = s.substr(pos, x == std::string::npos ? std::string::npos : x - pos);
    if (part.empty() || part.size() > 3 ||
        part.find_first_not_of("0123456789") != std::string::npos)
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

ScaffoldParams scaffold_params(const MeshOutputOptions& s, int n) {
  ScaffoldParams p;
  p.tiles = parse_tiles(s.tile, n);
  if (!(s.cell_size >= kMinCellSize && s.cell_size <= kMaxCellSize))
    throw OptionError(fmt::format("--cell-size: got {}; accepted: {:g} .. {:g} (in --units; "
                                  "a smaller unit for smaller cells)",
                                  s.cell_size, kMinCellSize, kMaxCellSize));
  p.cell_size = s.cell_size;
  if (!is_mesh_unit(s.units))
    throw OptionError(fmt::format("--units: got '{}'; accepted: {}", s.units, mesh_units_list()));
  p.units = s.units;
  try {
    p.solid = parse_solid_kind(s.solid);
  } catch (const std::invalid_argument& e) {
    throw OptionError(fmt::format("--solid: {}", e.what()));
  }
  p.other_phase = s.other_phase;
  p.keep_fragments = s.keep_fragments;
  if (p.solid == SolidKind::kSheet) {
    const double lo = s.cell_size / n, hi = 0.5 * s.cell_size;
    if (!(s.thickness >= lo && s.thickness <= hi))
      throw OptionError(fmt::format(
          "--thickness: got {}; accepted for --solid sheet: {:.6g} .. {:.6g} {} (one grid "
          "spacing of the N = {} field to half the cell size)",
          s.thickness, lo, hi, s.units, n));
    if (s.other_phase)
      throw OptionError("--other-phase: a sheet is the same for both phases; use it with "
                        "--solid surface|network");
    p.thickness = s.thickness;
  } else if (s.thickness != 0.0) {
    throw OptionError("--thickness: only accepted with --solid sheet");
  }
  return p;
}

MeshFormat mesh_output_format(const std::string& given, const std::filesystem::path& out) {
  if (out.empty()) throw OptionError("--out: a file name is required");
  std::string format = given;
  if (format.empty()) {
    format = out.extension().string();
    if (!format.empty()) format = format.substr(1);
  }
  MeshFormat f;
  try {
    f = parse_mesh_format(format);
  } catch (const std::invalid_argument& e) {
    throw OptionError(
        fmt::format("--format: {} (or give --out a .stl/.ply/.obj/.3mf name)", e.what()));
  }
  if (std::filesystem::is_directory(out))
    throw OptionError(fmt::format("--out: '{}' is a directory; give a file name", out.string()));
  return f;
}

MeshPlan plan_mesh_output(const MeshOutputOptions& s, int n) {
  MeshPlan plan;
  plan.params = scaffold_params(s, n);
  plan.out = s.out;
  plan.format = mesh_output_format(s.format, plan.out);
  return plan;
}

void write_mesh_with_report(const TriMesh& mesh, nlohmann::json report, const MeshPlan& plan,
                            const nlohmann::json& extra) {
  const auto t0 = std::chrono::steady_clock::now();
  namespace fs = std::filesystem;
  if (plan.out.has_parent_path()) ensure_directory(plan.out.parent_path());
  // FILE.json marks FILE complete: both are written whole under temporary names first, then
  // FILE is renamed into place and FILE.json after it, so a failure (a full disk) leaves
  // neither new file, and never a FILE.json beside a FILE it does not describe.
  const fs::path mesh_temp = temporary_name(plan.out);
  struct RemoveOnExit {
    fs::path path;
    ~RemoveOnExit() {
      std::error_code ec;
      fs::remove(path, ec);
    }
  } cleanup{mesh_temp};
  write_mesh(mesh_temp, plan.format, mesh, plan.params.units, plan.meta);
  report["file"] = plan.out.filename().string();
  report["file_bytes"] = fs::file_size(mesh_temp);
  report["format"] = mesh_format_extension(plan.format);
  report["write_seconds"] = seconds_since(t0);
  report["version"] = CMCSURF_VERSION;
  report.update(extra);
  AtomicWriter json(plan.out.string() + ".json");
  json.stream() << report.dump(2) << '\n';
  json.finish_writing();
  std::error_code ec;
  fs::rename(mesh_temp, plan.out, ec);
  if (ec)
    throw std::runtime_error(fmt::format("cannot rename '{}' to '{}': {}", mesh_temp.string(),
                                         plan.out.string(), ec.message()));
  json.commit();
}

void write_run_surface_mesh(const std::filesystem::path& dir, const Field& phi,
                            const std::string& format) {
  write_run_surface_mesh(dir, build_scaffold(phi, ScaffoldParams{}), format);
}

void write_run_surface_mesh(const std::filesystem::path& dir, const Scaffold& s,
                            const std::string& format) {
  MeshPlan plan;
  plan.format = parse_mesh_format(format);
  plan.out = dir / (std::string("surface.") + mesh_format_extension(plan.format));
  write_mesh_with_report(s.mesh, s.report, plan,
                         {{"note", "untiled phi = 1/2 surface; coordinates in unit cells"}});
}

}  // namespace cmcsurf
