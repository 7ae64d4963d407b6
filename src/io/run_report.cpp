#include "io/run_report.h"

#include <fmt/format.h>

#include "io/atomic_file.h"
#include "surfaces/initial.h"

namespace cmcsurf {

nlohmann::json params_json(const RunParams& p) {
  return {
      {"surface", p.surface},
      {"volume_fraction", p.volume_fraction},
      {"grid", p.grid},
      {"epsilon", p.epsilon},
      {"dt_factor", p.dt_factor},
      {"stop", p.stop == StopRule::kArea ? "area" : "phi"},
      {"tol", p.tol},
      {"max_steps", p.max_steps},
      {"smoother", p.smoother == SweepOrder::kRedBlack ? "redblack" : "lex"},
      {"radius", p.radius},
      {"seed", p.seed},
      {"noise_amplitude", p.noise_amplitude},
      {"prerelax_steps", p.prerelax_steps},
      {"prerelax_epsilon_factor", p.prerelax_epsilon_factor},
      {"bisection_tol", p.bisection_tol},
      {"bisection_max_it", p.bisection_max_it},
      {"mg_tol", p.solver.tol},
      {"max_vcycles", p.solver.max_vcycles},
      {"pre_sweeps", p.solver.fas.pre_sweeps},
      {"post_sweeps", p.solver.fas.post_sweeps},
      {"coarsest_max_sweeps", p.solver.fas.coarsest_max_sweeps},
      {"coarsest_reduction", p.solver.fas.coarsest_reduction},
  };
}

nlohmann::json measures_json(const Measures& m) {
  return {{"area", m.area},
          {"mean_curvature", m.mean_curvature},
          {"mean_curvature_mu", m.mean_curvature_mu},
          {"total_mean_curvature", m.total_mean_curvature},
          {"volume_fraction", m.volume_fraction},
          {"mass", m.mass},
          {"energy", m.energy}};
}

nlohmann::json run_report(const RunParams& p, const RunResult& r, int threads) {
  const SurfaceInfo* info = find_surface(p.surface);
  const bool nodal = r.bisection.has_value();
  nlohmann::json j;
  j["version"] = CMCSURF_VERSION;
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
  const int all_steps = r.steps + r.prerelax_steps;
  j["vcycles_per_step"] = all_steps ? double(r.vcycles) / all_steps : 0.0;
  j["seconds_per_vcycle"] = r.vcycles ? r.solver_seconds / double(r.vcycles) : 0.0;
  j["unconverged_steps"] = r.unconverged_steps;
  j["converged"] = r.converged;
  j["stop_reason"] = r.stop_reason;
  const nlohmann::json final_measures = measures_json(r.final);
  for (auto& [key, value] : final_measures.items()) j[key] = value;
  j["final_d_area"] = r.history.empty() ? 0.0 : r.history.back().d_area;
  j["final_d_phi"] = r.history.empty() ? 0.0 : r.history.back().d_phi;
  j["initial"] = measures_json(r.initial);
  if (nodal) {
    j["bisection"] = {{"beta", r.bisection->beta},
                      {"v_ave", r.bisection->v_ave},
                      {"iterations", r.bisection->iterations},
                      {"mass_before_shift", r.mass_before_shift}};
  }
  j["balanced"] = info ? nlohmann::json(info->balanced) : nlohmann::json();
  j["wall_seconds"] = r.wall_seconds;
  j["solver_seconds"] = r.solver_seconds;
  j["threads"] = threads;
  j["parameters"] = params_json(p);
  j["conventions"] = {
      {"phase_1", "phi > 1/2"},
      {"mean_curvature", "Appendix B estimator, positive when phase 1 is convex (1/r for a ball)"},
      {"mean_curvature_mu", "mu/2 = 3 sqrt(2) nu / eps with nu = W'(phi) - eps^2 Lap phi, "
                            "|grad phi|^2-weighted (Gibbs-Thomson; the paper's mu/3 is 2/3 of it, see docs/method.md)"},
      {"volume_fraction", "fraction of cells with phi > 1/2"},
      {"mass", "mean of phi"}};
  return j;
}

void write_history_csv(const std::filesystem::path& path, const std::vector<StepRecord>& history) {
  std::string out = "step,stage,time,area,d_area,d_phi,energy,mass,vcycles,residual,elapsed\n";
  for (const StepRecord& r : history)
    out += fmt::format("{},{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{},{:.6e},{:.6f}\n",
                       r.step, r.stage, r.time, r.area, r.d_area, r.d_phi, r.energy, r.mass,
                       r.vcycles, r.residual, r.elapsed);
  write_file_atomic(path, out);
}

}  // namespace cmcsurf
