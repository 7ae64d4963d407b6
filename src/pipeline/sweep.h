// Families of CMC surfaces: one run per surface and volume fraction (Section 4.5, Fig. 11),
// from the nodal formula or by continuation from the neighbouring member.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "measure/quality.h"
#include "pipeline/cmc.h"

namespace cmcsurf {

// "start:stop:step" (inclusive of stop up to rounding) or a list "a,b,c" or one value. Every
// fraction must lie in (0, 1), start <= stop, step > 0. Throws std::invalid_argument saying what
// is wrong and what is accepted.
std::vector<double> parse_volume_fractions(const std::string& spec);

// A comma-separated list of nodal surfaces; commas inside parentheses belong to an expr:
// formula. Throws std::invalid_argument for an unknown or non-nodal surface, or an empty list.
std::vector<std::string> parse_surface_list(const std::string& spec);

// Folder name of a member: "G_0.30" (two decimals unless more are needed); expr: surfaces are
// named "expr<k>" by their position k in the list.
std::string member_name(const std::string& surface, int surface_index, double alpha);

// A member name read back (from sweep.json's surfaces and fractions) before it is joined onto
// the sweep's folder: one plain path component as member_name makes them (letters, digits and
// "_.+-", not "." or "..", at most 255 bytes), so never "../x/G_0.30" or "/abs". Throws
// std::invalid_argument naming `source` (the file it came from) and the name.
void check_member_name(const std::string& name, const std::string& source);
// member_name, checked as above.
std::string checked_member_name(const std::string& surface, int surface_index, double alpha,
                                const std::string& source);

struct SweepParams {
  RunParams run;  // surface and volume_fraction are set per member
  std::vector<std::string> surfaces;
  std::vector<double> fractions;
  bool continuation = false;  // start each member from the previous one of its family
};

// sweep.json read back (sweep --resume): the sweep (surfaces, volume_fractions, continuation,
// parameters as params_from_json reads them, all of it passing check_sweep_params, every member
// name passing check_member_name) and the output options a resume may restore: of "outputs",
// threads, float32, no_preview, no_report, no_plot, plot_diffuse and checkpoint_every where
// present, each checked (type, range; integers never wrapped). "python" and "plot_script" are
// never returned: a resumed sweep does not take an executable from a file. The informational
// keys (members, threads, wall_seconds, mpi) are checked too; other keys are ignored. Throws
// std::invalid_argument naming the key and what is accepted.
struct SweepJson {
  SweepParams sweep;
  nlohmann::json outputs = nlohmann::json::object();
};
SweepJson parse_sweep_json(const nlohmann::json& j);

// The checks parse_surface_list, parse_volume_fractions and check_run_params (without the
// per-member surface and fraction) make, on a sweep read back from sweep.json: at least one
// nodal surface, 1 to 1000 fractions in (0, 1). Throws std::invalid_argument naming the problem.
void check_sweep_params(const SweepParams& params);

struct SweepMember {
  int index = 0;  // over the whole sweep
  int count = 0;
  std::string surface;
  double alpha = 0.0;
  std::string name;
  std::string started_from;  // "nodal" or the previous member's name
  RunParams params;
};

// Continuation start from the neighbour's converged field (at volume fraction neighbour_alpha):
// with Constraint::kMass shifted to mean alpha (step 5) and relaxed (step 6); with kVolume
// shifted by alpha - neighbour_alpha and handed to relax_to_volume_fraction, whose secant
// iteration on the mass (the one run_cmc uses) brings V to alpha within volume_tol.
RunResult run_from_neighbour(const Field& neighbour, double neighbour_alpha,
                             const RunParams& params, const RunContext& context = {},
                             FinalFieldCache* cache = nullptr);

// CMC quality of a run's final field (docs/families.md), a pipeline stage after the solve: the
// local mean curvature over the surface (measure/sharp_surface.h) and, for nodal surfaces, the
// same of the nodal surface {F = c} at the final field's sharp volume fraction, plus Appendix B's
// area and mean curvature of that nodal surface's tanh profile at epsilon. On a block of a
// decomposed field every process takes part and gets the same result (the samples of its block
// reduced over the processes).
CmcQuality measure_cmc_quality(const Field& relaxed, const RunParams& params);
// The same from psi = tanh_profile_inverse(relaxed) and the relaxed field's sharp volume
// fraction, when the caller has them (the stages after a run share one psi).
// relaxed_samples: the local H samples of psi's zero set, if the caller has them.
CmcQuality measure_cmc_quality_psi(const Field& psi, double volume_fraction,
                                   const RunParams& params,
                                   const std::vector<CurvatureSample>* relaxed_samples = nullptr);

// How a member starts when a sweep resumes (sweep --resume): from scratch, from its own
// checkpoint, or not at all, its folder holding it complete; `field` is then its final phi
// (whole grid), which continues the family. kElsewhere: another group of processes runs it
// (a sweep across nodes); with continuation a group runs whole families, never part of one.
struct MemberStart {
  enum class Kind { kRun, kResume, kSkip, kElsewhere };
  Kind kind = Kind::kRun;
  std::shared_ptr<const Checkpoint> checkpoint;  // kResume
  Field field;                                   // kSkip, with continuation
};
using PlanFn = std::function<MemberStart(const SweepMember&)>;

// Runs every member, surfaces outermost, fractions in the given order. `plan` (may be empty:
// every member runs) is asked first; `starting` is called before a member runs, `done` after
// and is handed the result with the final measures' psi and samples that the run returned
// beside it (for run_outputs); the field is kept here only for the next member's continuation,
// copied before. A RunInterrupted from a member's run passes through. Under
// context.decomposition every process of it calls this alike and gets its blocks.
using MemberFn = std::function<void(const SweepMember&, RunResult, FinalFieldCache)>;
void run_sweep(const SweepParams& params, const std::function<void(const SweepMember&)>& starting,
               const MemberFn& done, const RunContext& context = {}, const PlanFn& plan = {});


}  // namespace cmcsurf
