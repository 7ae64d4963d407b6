// report.json and history.csv of a run (the names and keys are a contract with users' scripts).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

#include "pipeline/cmc.h"

namespace cmcsurf {

// Every parameter of a run, as the command line names them.
nlohmann::json params_json(const RunParams& p);
nlohmann::json measures_json(const Measures& m);

// The report: the required keys at top level (surface, grid, epsilon, dt,
// volume_fraction_target, steps, vcycles, converged, area, mean_curvature, mean_curvature_mu,
// total_mean_curvature, volume_fraction, mass, energy, wall_seconds, version) plus details
// and "parameters".
nlohmann::json run_report(const RunParams& p, const RunResult& r, int threads);

// history.csv: step, stage, time, area, d_area, d_phi, energy, mass, vcycles, residual, elapsed.
void write_history_csv(const std::filesystem::path& path, const std::vector<StepRecord>& history);

}  // namespace cmcsurf
