#include "mesh_options.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <vector>

#include "cli_common.h"
#include "common/atomic_file.h"
#include "common/input_file.h"
#include "io/json_file.h"
#include "io/pvti.h"
#include "io/vti.h"
#include "pipeline/member_topology.h"
#include "run_control.h"

namespace cmcsurf::cli {

namespace {

constexpr int kMaxCellsPerAxis = 2048;

}  // namespace

void add_mesh_output_options(CLI::App& app, MeshOptionStrings& s, bool with_sheet) {
  app.add_option("--tile", s.tile, "Unit cells along x, y, z: AxBxC (or A for AxAxA)")
      ->capture_default_str();
  app.add_option("--cell-size", s.cell_size, "Edge of one unit cell in output units")
      ->capture_default_str();
  app.add_option("--units", s.units,
                 std::string("Length unit of the coordinates: ") + mesh_units_list())
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
    app.add_flag("--keep-fragments", s.keep_fragments,
                 "Solids: keep the pieces the box cuts off (default: removed and reported)");
  if (with_sheet)
    app.add_option("--thickness", s.thickness, "Sheet wall thickness in output units");
  app.add_flag("--accept-topology-change", s.accept_topology_change,
               "Mesh a member whose topology (Euler characteristic in its report.json) differs "
               "from its family's (euler_characteristic_start); refused by default");
  app.add_option("--format", s.format,
                 std::string("Mesh format: ") + mesh_format_list() + " (default: from --out)");
  app.add_option("--out", s.out, "Output mesh file (a report goes to FILE.json)")->required();
}

MeshPlan finish_mesh_output_options(const MeshOptionStrings& s, int n) {
  try {
    return plan_mesh_output(s, n);
  } catch (const OptionError& e) {
    throw UsageError(e.what());
  }
}

Field load_phi(const std::string& from, const std::string& option,
               std::map<std::string, std::string>* metadata) {
  std::filesystem::path path(from);
  if (std::filesystem::is_directory(path)) {
    try {
      path = run_field_file(path);  // field.vti, or field.pvti of a decomposed run
    } catch (const std::runtime_error& e) {
      throw UsageError(fmt::format("{}: {}", option, e.what()));
    }
  }
  try {
    require_regular_file(path, option);
  } catch (const std::runtime_error& e) {
    throw UsageError(e.what());
  }
  if (!std::filesystem::is_regular_file(path))
    throw UsageError(fmt::format("{}: '{}' is neither a run directory with field.vti (or "
                                 "field.pvti) nor a .vti or .pvti file",
                                 option, from));
  VtiReadOptions options;
  options.ghost = 2;
  options.max_n = kMaxCellsPerAxis;  // refused before anything is allocated
  options.only = "phi";              // the phase field cmcsurf writes; no other array is read
  VtiData data = read_field_file(path, options);
  if (metadata) *metadata = data.metadata;
  return std::move(data.arrays.at("phi"));
}

std::vector<FileRole> field_inputs(const std::string& from, const std::string& option) {
  namespace fs = std::filesystem;
  std::vector<FileRole> reads;
  fs::path field(from);
  if (fs::is_directory(field)) {
    try {
      field = run_field_file(field);
    } catch (const std::runtime_error&) {
      return reads;  // load_phi names the problem
    }
  }
  reads.push_back({field, option});
  std::error_code ec;
  if (field.extension() == ".pvti" && fs::is_directory(pvti_piece_dir(field), ec))
    for (const auto& e : fs::directory_iterator(pvti_piece_dir(field), ec))
      reads.push_back({e.path(), option + "'s piece"});
  if (const fs::path report = field_run_report(from); !report.empty())
    reads.push_back({report, option + "'s report.json"});
  return reads;
}

std::filesystem::path field_run_report(const std::string& from) {
  namespace fs = std::filesystem;
  const fs::path path(from);
  fs::path report;
  if (fs::is_directory(path)) report = path / "report.json";
  else if (path.filename() == kRunFieldVti || path.filename() == kRunFieldPvti)
    report = path.parent_path() / "report.json";
  return !report.empty() && fs::is_regular_file(report) ? report : fs::path();
}

void refuse_overwriting_inputs(const std::vector<FileRole>& reads,
                               const std::filesystem::path& out) {
  try {
    cmcsurf::check_outputs_are_not_inputs(
        reads, {{out, "--out"}, {out.string() + ".json", "--out's report (FILE.json)"}});
  } catch (const OptionError& e) {
    throw UsageError(e.what());
  }
}

void check_field_topology(const std::string& from, bool accept) {
  const std::filesystem::path report = field_run_report(from);
  if (accept || report.empty()) return;
  nlohmann::json r;
  try {
    r = read_json_file(report);
  } catch (const std::exception&) {
    return;  // not a report of ours: nothing to compare with
  }
  if (const auto t = member_topology(r))
    check_member_topology(*t, fmt::format("'{}'", from), "--accept-topology-change");
}

}  // namespace cmcsurf::cli
