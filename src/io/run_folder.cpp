#include "io/run_folder.h"

#include <chrono>

#include <fmt/format.h>

#include <string>
#include <vector>

#include "common/wall_clock.h"
#include "common/atomic_file.h"
#include "grid/check.h"
#include "io/json_file.h"
#include "io/run_report.h"
#include "io/pvti.h"
#include "io/vti.h"

namespace cmcsurf {

void clear_run_outputs(const std::filesystem::path& dir, bool keep_field) {
  namespace fs = std::filesystem;
  // report.json first: from here until it is written again the folder reads as incomplete.
  std::vector<fs::path> stale = {dir / "report.json"};
  for (const char* name : {"history.csv", "curvature_histogram.csv", "curvature_distribution.csv",
                           "preview.png", "youngs_modulus.png", "report.html"})
    stale.push_back(dir / name);
  for (const char* ext : {"stl", "ply", "obj", "3mf"}) {
    stale.push_back(dir / (std::string("surface.") + ext));
    stale.push_back(dir / (std::string("surface.") + ext + ".json"));
  }
  for (const fs::path& f : stale) {
    std::error_code ec;
    fs::remove(f, ec);
    if (ec)
      throw std::runtime_error(
          fmt::format("cannot remove the earlier run's '{}': {}", f.string(), ec.message()));
  }
  if (!keep_field) remove_run_field(dir);  // field.vti, or field.pvti and its pieces
}

std::map<std::string, std::string> run_field_metadata(const RunParams& p, const RunResult& r,
                                                      const nlohmann::json& report) {
  const nlohmann::json& target = report["volume_fraction_target"];
  return {{"surface", p.surface},
          {"volume_fraction_target",
           target.is_null() ? "none" : fmt::format("{}", target.get<double>())},
          {"epsilon", fmt::format("{}", p.epsilon)},
          {"grid", fmt::format("{}", p.grid)},
          {"area", fmt::format("{:.17g}", r.final.area)},
          {"mean_curvature", fmt::format("{:.17g}", r.final.mean_curvature)},
          {"version", CMCSURF_VERSION}};
}

nlohmann::json decomposition_json(const Decomposition& world) {
  nlohmann::json ranks = {{"mpi_ranks", world.ranks()},
                          {"process_grid", {world.dims()[0], world.dims()[1], world.dims()[2]}}};
  if (world.distributed()) {
    const CommStats& c = world.stats();  // rank 0's share (docs/scaling.md)
    ranks["mpi_rank0"] = {{"halo_bytes_sent", c.halo_bytes},
                          {"halo_messages", c.halo_messages},
                          {"gather_bytes_sent", c.gather_bytes},
                          {"collectives", c.collectives},
                          {"comm_seconds", c.seconds}};
  }
  return ranks;
}

nlohmann::json run_folder_report(const RunParams& p, const RunResult& r,
                                 const CmcQuality& quality, int threads,
                                 const nlohmann::json& extra) {
  nlohmann::json report = run_report(p, r, threads);
  report.update(quality_json(quality, r.final.area));
  if (extra.is_object()) report.update(extra);
  return report;
}

double write_run_field_pieces(const std::filesystem::path& dir, const RunParams& p,
                              const RunResult& r, const CmcQuality& quality, int threads,
                              bool float32, const nlohmann::json& extra) {
  const auto t0 = WallClock::now();
  CMCSURF_DCHECK(halo_is_current(r.phi));
  write_run_field(dir, {{"phi", &r.phi}}, float32,
                  run_field_metadata(p, r, run_folder_report(p, r, quality, threads, extra)));
  return seconds_since(t0);
}

nlohmann::json write_run_folder(const std::filesystem::path& dir, const RunParams& p,
                                const RunResult& r, const RunFieldSource& field,
                                const CmcQuality& quality, int threads, bool float32,
                                const nlohmann::json& extra,
                                const std::function<void(const nlohmann::json&)>& extra_files) {
  nlohmann::json report = run_folder_report(p, r, quality, threads, extra);
  const auto t0 = std::chrono::steady_clock::now();
  const auto* pieces = std::get_if<FieldPiecesWritten>(&field);
  const bool field_written = pieces != nullptr;
  const double field_seconds = pieces ? pieces->seconds : 0.0;
  ensure_directory(dir);
  clear_run_outputs(dir, field_written);
  write_curvature_histogram_csv(dir / "curvature_histogram.csv", quality);
  write_curvature_distribution_csv(dir / "curvature_distribution.csv", quality);
  write_history_csv(dir / "history.csv", r.history);
  if (const auto* whole = std::get_if<std::reference_wrapper<const Field>>(&field)) {
    const Field& phi = whole->get();
    std::vector<VtiArray> arrays = {{"phi", &phi}};
    // --distance-field: the profile's signed distance beside phi (whole grids).
    if (r.distance.n() == phi.n() && r.distance.size() == phi.size())
      arrays.push_back({"distance", &r.distance});
    write_run_field(dir, arrays, float32, run_field_metadata(p, r, report));
  }
  if (extra_files) extra_files(report);
  // The files before report.json; report.json itself and a page written after it are not in it.
  report["write_seconds"] =
      field_seconds + seconds_since(t0);
  write_json_atomic(dir / "report.json", report);
  return report;
}

}  // namespace cmcsurf
