// A run's folder as `cmcsurf run` and `sweep` write it, and as Python's Result.save() writes
// it: the files of io/run_report.h, field.vti, and report.json last. Writes only: everything
// in it was computed before.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <variant>

#include <nlohmann/json.hpp>

#include "measure/quality.h"
#include "parallel/decomposition.h"
#include "model/run.h"

namespace cmcsurf {

// Removes the outputs an earlier run left in dir (report.json first), so that a run into an
// existing folder never leaves new files beside an old report, nor old ones beside a new one.
// keep_field: leave field.vti / field.pvti (this run's, written before by every process).
void clear_run_outputs(const std::filesystem::path& dir, bool keep_field = false);

// The metadata of a run's field file (the cmcsurf comment of field.vti / field.pvti).
std::map<std::string, std::string> run_field_metadata(const RunParams& p, const RunResult& r,
                                                      const nlohmann::json& report);

// report.json keys of the process layout: mpi_ranks, process_grid and, on several processes,
// rank 0's communication counters (docs/scaling.md).
nlohmann::json decomposition_json(const Decomposition& world);

// The report of a run folder: run_report() plus the CMC quality keys (computed by the
// pipeline's measure_cmc_quality) plus `extra` (which may override, e.g. the target of a
// continued sweep member).
nlohmann::json run_folder_report(const RunParams& p, const RunResult& r,
                                 const CmcQuality& quality, int threads,
                                 const nlohmann::json& extra = {});

// A decomposed run's field.pvti with one piece per process (io/pvti.h), written by every
// process (collective) before the group's rank 0 writes the rest with write_run_folder
// (FieldPiecesWritten with these seconds). The pieces share their faces: r.phi arrives with
// valid ghosts, as every entry point of pipeline/cmc.h returns it (the final measures exchange
// them last). Returns the wall time.
double write_run_field_pieces(const std::filesystem::path& dir, const RunParams& p,
                              const RunResult& r, const CmcQuality& quality, int threads,
                              bool float32, const nlohmann::json& extra);

// The field file of a run folder: written by write_run_folder from the whole field, or written
// before by every process (write_run_field_pieces) in `seconds`, which write_seconds includes.
struct FieldPiecesWritten {
  double seconds = 0.0;
};
using RunFieldSource = std::variant<std::reference_wrapper<const Field>, FieldPiecesWritten>;

// A run's folder: history.csv, curvature_histogram.csv, field.vti, then whatever `extra_files`
// writes (the surface mesh, preview.png, report.html; it gets the report to be written), and
// report.json (run_folder_report) last, since it marks a complete run: a failure before it
// leaves no report.json. The folder must be the caller's (io/output_folder.h). An earlier run's
// outputs in dir are removed first (clear_run_outputs), the field file's too unless `field` says
// the caller wrote it. Returns the report.
nlohmann::json write_run_folder(const std::filesystem::path& dir, const RunParams& p,
                                const RunResult& r, const RunFieldSource& field,
                                const CmcQuality& quality, int threads, bool float32,
                                const nlohmann::json& extra = {},
                                const std::function<void(const nlohmann::json&)>& extra_files = {});

}  // namespace cmcsurf
