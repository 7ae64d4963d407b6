// The sweep.json reader (pipeline/sweep.h parse_sweep_json, which sweep --resume uses) on
// arbitrary text: it either returns a sweep that passes the command line's checks, member names
// that stay inside the sweep's folder and no executable among the outputs, or throws
// std::invalid_argument naming the key.
#include <string>

#include <nlohmann/json.hpp>

#include "fuzz_target.h"
#include "model/option_checks.h"
#include "model/run_options.h"
#include "pipeline/sweep.h"

CMCSURF_FUZZ_TARGET(sweep_json) {
  using cmcsurf::fuzz::require;
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(input.begin(), input.end());
  } catch (const nlohmann::json::exception&) {
    return cmcsurf::fuzz::Outcome::refused;  // not JSON: the caller's read refuses it
  }
  cmcsurf::SweepJson s;
  try {
    s = cmcsurf::parse_sweep_json(j);
  } catch (const std::invalid_argument&) {
    return cmcsurf::fuzz::Outcome::refused;
  }
  const cmcsurf::SweepParams& sp = s.sweep;
  require(!sp.surfaces.empty() && !sp.fractions.empty(), "an empty sweep");
  for (double alpha : sp.fractions)
    require(alpha > 0.0 && alpha < 1.0, "a fraction outside (0, 1)");
  for (std::size_t i = 0; i < sp.surfaces.size(); ++i)
    for (double alpha : sp.fractions) {
      const std::string name = cmcsurf::member_name(sp.surfaces[i], int(i), alpha);
      require(name.find('/') == std::string::npos && name != ".." && name != ".",
              "member name '" + name + "' leaves the folder");
    }
  cmcsurf::check_sweep_params(sp);  // a finding if it throws: parse_sweep_json promised it
  require(s.outputs.is_object(), "outputs is not an object");
  require(!s.outputs.contains("python") && !s.outputs.contains("plot_script"),
          "an executable among the outputs");
  if (s.outputs.contains("threads"))
    require(cmcsurf::check_threads(s.outputs["threads"].get<long long>()).empty(),
            "threads out of range");
  return cmcsurf::fuzz::Outcome::parsed;
}
