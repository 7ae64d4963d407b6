// Finishing a run folder, one function for `cmcsurf run`, each member of `cmcsurf sweep` and
// Python's Result.save(): the stages after the solve that the folder shows (the properties
// stage and its picture, the surface mesh), field.pvti's pieces under a decomposition, the
// process layout, then write_run_folder (io/run_folder.h) with preview.png and report.html,
// and the finished run's checkpoint removed. The quality, preview and page come computed
// (run_outputs, pipeline/run_outputs.h, or run_pictures below).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "parallel/decomposition.h"
#include "pipeline/cmc.h"
#include "pipeline/properties_stage.h"
#include "pipeline/run_outputs.h"

namespace cmcsurf {

struct RunFolderOptions {
  int threads = 1;
  bool float32 = false;            // field.vti / field.pvti in single precision
  bool pictures = true;            // youngs_modulus.png with the properties stage
  std::string mesh_format;         // `run --mesh`: surface.FORMAT ("": none)
  PropertiesStage properties;      // --properties (enabled: the stage runs)
  bool remove_checkpoint = true;   // the run is complete: its checkpoint.bin goes
  // The process layout keys (decomposition_json) and every process's peak memory, added after
  // the last collective (`run`); null: the caller put its own layout keys in `extra` (a sweep's
  // group, Python).
  const Decomposition* layout = nullptr;
};

// The --properties stage's output options as a checkpoint's and sweep.json's "outputs" keep
// them (properties, properties_*); `porosity`: --properties-porosity as given ("": none).
nlohmann::json properties_outputs_json(const PropertiesStage& stage, const std::string& porosity);

// What finish_run_folder did, on the process that wrote the folder (`writer`).
struct FinishedRun {
  bool writer = false;    // this process wrote report.json and the files beside it
  nlohmann::json report;  // the report written (writer only)
};

// phi: r.phi, the whole grid or this process's block under `group` (every process of it calls
// this: collective), whose rank 0 writes the folder; the others write their field.pvti piece.
// `extra`: report.json keys of the caller (checkpoints, member, ...). A failure throws; the
// folder then has no report.json.
FinishedRun finish_run_folder(const std::filesystem::path& dir, const RunParams& p,
                              const RunResult& r, RunOutputs& outputs,
                              const RunFolderOptions& o,
                              nlohmann::json extra);

// Python's Result.save(): preview.png's picture and report.html's meshes of a finished run
// whose quality stage ran before (the CLI takes all three from run_outputs).
RunOutputs run_pictures(const RunParams& p, const RunResult& r, const CmcQuality& quality,
                        bool preview, bool page);

}  // namespace cmcsurf
