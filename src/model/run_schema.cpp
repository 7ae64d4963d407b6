#include "model/run_schema.h"

#include <algorithm>
#include <limits>

#include "multigrid/fas.h"
#include "model/option_checks.h"
#include "model/run_options.h"
#include "surfaces/initial.h"

namespace cmcsurf {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Ranges as the messages state them.
constexpr RunRange open(double lo, double hi) { return {lo, hi, false, false}; }
constexpr RunRange closed(double lo, double hi) { return {lo, hi, true, true}; }
constexpr RunRange at_least(double lo) { return {lo, kInf, true, false}; }
constexpr RunRange above(double lo) { return {lo, kInf, false, false}; }  // finite too

using S = RunOptionScope;

// The command line's order: its help lists the options so.
const std::vector<RunOption>& table() {
  static const std::vector<RunOption> t = {
      {.key = "surface",
       .cli = "--surface",
       .help = "Initial surface: P, D, G (Eqs. 7-9), sphere, cube, noise, other nodal surfaces "
               "(see `cmcsurf surfaces`)",
       .unit = "",
       .scope = S::kSurface,
       .solver_group = false,
       .ref = RunMember<std::string>([](RunParams& p) -> std::string& { return p.surface; }),
       .optional_in_json = true},  // sweep.json's parameters: the members have their own
      {.key = "volume_fraction",
       .cli = "--volume-fraction",
       .help = "Target volume fraction alpha of phase 1 (phi > 1/2), in (0, 1)",
       .unit = "",
       .scope = S::kSurface,
       .solver_group = false,
       .ref = RunMember<double>([](RunParams& p) -> double& { return p.volume_fraction; }),
       .optional_in_json = true},  // the same
      // --structure double: two networks in a matrix (model/run.h's Structure).
      {.key = "structure",
       .cli = "--structure",
       .help = "Nodal surfaces: single (phase 1 = {F > c}) or double (phase 1 = {|F| > c}: two "
               "networks in a matrix, seeded at --volume-fraction without pre-relaxation; "
               "with --constrain components each keeps its volume; one process)",
       .unit = "",
       .scope = S::kSurface,
       .solver_group = false,
       .ref = RunChoice{{"single", "double"},
                        [](const RunParams& p) { return int(p.structure); },
                        [](RunParams& p, int i) { p.structure = Structure(i); }},
       .optional_in_json = true},  // reports written before the option existed: single
      {.key = "grid",
       .cli = "--grid",
       .help = "Cells per side N (m * 2^k, m in {1,3,5,7}, N >= 8)",
       .unit = "cells per side",
       .scope = S::kGrid,
       .solver_group = false,
       .ref = RunMember<int>([](RunParams& p) -> int& { return p.grid; }),
       .paper = [](RunParams& p) { p.grid = kPaperGrid; }},
      {.key = "epsilon",
       .cli = "--epsilon",
       .help = "Interface parameter epsilon (> 0)",
       .unit = "unit cell",
       .scope = S::kSolver,
       .solver_group = false,
       .ref = RunMember<double>([](RunParams& p) -> double& { return p.epsilon; }),
       .range = open(0.0, 1.0),
       .accepted = "0 < E < 1"},
      {.key = "dt_factor",
       .cli = "--dt-factor",
       .help = "Time step dt = C * h",
       .unit = "h",
       .scope = S::kSolver,
       .solver_group = false,
       .ref = RunMember<double>([](RunParams& p) -> double& { return p.dt_factor; }),
       .range = above(0.0),
       .accepted = "C > 0 (dt = C h)"},
      {.key = "stop",
       .cli = "--stop",
       .help = "Stop rule: area (|A^{n+1} - A^n| <= tol, Section 4.5) or phi "
               "(||phi^{n+1} - phi^n|| <= tol, Section 4.3)",
       .unit = "",
       .scope = S::kSolver,
       .solver_group = false,
       .ref = RunChoice{{"area", "phi"},
                        [](const RunParams& p) { return p.stop == StopRule::kArea ? 0 : 1; },
                        [](RunParams& p, int i) {
                          p.stop = i == 0 ? StopRule::kArea : StopRule::kPhi;
                        }}},
      {.key = "tol",
       .cli = "--tol",
       .help = "Tolerance of the stop rule",
       .unit = "",
       .scope = S::kSolver,
       .solver_group = false,
       .ref = RunMember<double>([](RunParams& p) -> double& { return p.tol; }),
       .range = above(0.0),
       .accepted = "T > 0"},
      {.key = "max_steps",
       .cli = "--max-steps",
       .help = "Limit on relaxation steps",
       .unit = "time steps",
       .scope = S::kSolver,
       .solver_group = false,
       .ref = RunMember<int>([](RunParams& p) -> int& { return p.max_steps; }),
       .range = at_least(1),
       .accepted = "K >= 1"},
      {.key = "smoother",
       .cli = "--smoother",
       .help = "Gauss-Seidel ordering: redblack (parallel) or lex (as printed, serial)",
       .unit = "",
       .scope = S::kSolver,
       .solver_group = false,
       .ref = RunChoice{{"redblack", "lex"},
                        [](const RunParams& p) {
                          return p.smoother == SweepOrder::kRedBlack ? 0 : 1;
                        },
                        [](RunParams& p, int i) {
                          p.smoother = i == 0 ? SweepOrder::kRedBlack : SweepOrder::kLexicographic;
                        }}},
      {.key = "constrain",
       .cli = "--constrain",
       .help = "What step 6 holds at --volume-fraction: volume (the sharp volume fraction of "
               "phi > 1/2, by mass corrections after step 6), mass (the paper's Section 4.4 "
               "as printed) or components (the sharp volume of each connected component of "
               "phi > 1/2, scaled to sum to alpha, after every step: the networks of a double "
               "structure; one process); no effect for sphere, cube, noise",
       .unit = "",
       .scope = S::kSolver,
       .solver_group = false,
       .ref = RunChoice{{"volume", "mass", "components"},
                        [](const RunParams& p) { return int(p.constrain); },
                        [](RunParams& p, int i) { p.constrain = Constraint(i); }}},
      {.key = "volume_tol",
       .cli = "--volume-tol",
       .help = "--constrain volume: stop correcting when |V - alpha| <= this",
       .unit = "",
       .scope = S::kSolver,
       .solver_group = false,
       .ref = RunMember<double>([](RunParams& p) -> double& { return p.volume_tol; }),
       .range = open(0.0, 0.1),
       .accepted = "0 < T < 0.1"},
      {.key = "radius",
       .cli = "--radius",
       .help = "Sphere radius (surface sphere), in (0, 0.5)",
       .unit = "unit cell",
       .scope = S::kInitial,
       .solver_group = false,
       .ref = RunMember<double>([](RunParams& p) -> double& { return p.radius; }),
       .range = open(0.0, 0.5),
       .accepted = "0 < R < 0.5"},
      {.key = "seed",
       .cli = "--seed",
       .help = "Random seed (surface noise)",
       .unit = "",
       .scope = S::kInitial,
       .solver_group = false,
       .ref = RunMember<std::uint64_t>([](RunParams& p) -> std::uint64_t& { return p.seed; }),
       .integer_check = check_seed},
      {.key = "mg_tol",
       .cli = "--mg-tol",
       .help = "V-cycles stop when the defect norm sqrt(mean (dt d_phi)^2 + mean d_nu^2) is "
               "below this",
       .unit = "",
       .scope = S::kSolver,
       .solver_group = true,
       .ref = RunMember<double>([](RunParams& p) -> double& { return p.solver.tol; }),
       .range = above(0.0),
       .accepted = "> 0"},
      {.key = "fast",
       .cli = "--fast",
       .help = "Fast mode, the default (--paper turns it off): the options below marked (fast) "
               "take their fast values unless given (coarse-to-fine continuation, --mg-rtol "
               "1e-2, --extrapolate, --dt-max-factor 8, --continued-dt-factor 8, "
               "--mg-rtol-finest 0.1, --equilibrium-tol 1e-3 (128/N)^2, --anderson-depth 3); "
               "the surface agrees with the paper-faithful run to about 1e-4 in "
               "area and is closer to the equilibrium (docs/performance.md)",
       .unit = "",
       .scope = S::kSolver,
       .solver_group = false,
       .ref = RunMember<bool>([](RunParams& p) -> bool& { return p.fast; }),
       .paper = [](RunParams& p) { p.fast = false; }},
      {.key = "paper",
       .cli = "--paper",
       .help = "The paper-faithful algorithm of Section 4.4 as before 2026-11-27: no fast mode, "
               "--grid 64 unless given, the paper's stop rule (--stop, --tol); not with --fast",
       .unit = "",
       .scope = S::kSolver,
       .solver_group = false,
       .ref = RunMember<bool>([](RunParams& p) -> bool& { return p.paper; }),
       .optional_in_json = true},  // absent before 2026-11-27: false
      {.key = "mg_rtol",
       .cli = "--mg-rtol",
       .help = "(fast) Also stop V-cycles when the defect is below this times the step's first "
               "defect (0: off, the paper-faithful default; --fast uses 1e-2)",
       .unit = "",
       .scope = S::kSolver,
       .solver_group = true,
       .ref = RunMember<double>([](RunParams& p) -> double& { return p.solver.rtol; }),
       .range = {0.0, 1.0, true, false},
       .accepted = "0 <= R < 1",
       .fast = [](RunParams& p, bool) { p.solver.rtol = kFastMgRtol; }},
      {.key = "mg_rtol_finest",
       .cli = "--mg-rtol-finest",
       .help = "(fast) --mg-rtol on the finest grid of a coarse-to-fine run, which starts from "
               "the relaxed coarser field (0: --mg-rtol there too; --fast uses 0.1)",
       .unit = "",
       .scope = S::kSolver,
       .solver_group = true,
       .ref = RunMember<double>([](RunParams& p) -> double& { return p.mg_rtol_finest; }),
       .range = {0.0, 1.0, true, false},
       .accepted = "0 (as --mg-rtol) <= R < 1",
       .fast = [](RunParams& p, bool) { p.mg_rtol_finest = kFastMgRtolFinest; },
       .optional_in_json = true},  // absent before 2026-11-25: off
      {.key = "coarse_levels",
       .cli = "--coarse-levels",
       .help = "(fast) Coarse-to-fine continuation: run on N/2^K first, then interpolate and "
               "finish on each finer grid (0: off, the paper's procedure; --fast takes K <= 2 "
               "with N/2^K >= 32; nodal surfaces only)",
       .unit = "halvings of the grid",
       .scope = S::kSolver,
       .solver_group = true,
       .ref = RunMember<int>([](RunParams& p) -> int& { return p.coarse_levels; }),
       .range = closed(0, 4),
       .accepted = "0..4",
       .fast =
           [](RunParams& p, bool check_surface) {
             if (check_coarsenable(p.grid).empty() &&
                 (!check_surface || is_nodal_surface(p.surface)))
               p.coarse_levels = fast_coarse_levels(p.grid);
           }},
      {.key = "extrapolate",
       .cli = "--extrapolate,!--no-extrapolate",
       .help = "(fast) Start each step's V-cycles from the linear extrapolation of the last two "
               "steps instead of the last step",
       .unit = "",
       .scope = S::kSolver,
       .solver_group = true,
       .ref = RunMember<bool>([](RunParams& p) -> bool& { return p.solver.extrapolate; }),
       .fast = [](RunParams& p, bool) { p.solver.extrapolate = true; }},
      {.key = "dt_max_factor",
       .cli = "--dt-max-factor",
       .help = "(fast) Adaptive time steps: during each relaxation at epsilon, dt doubles after "
               "every converged step up to this times h (0: fixed dt, the paper's; --fast uses 8)",
       .unit = "h",
       .scope = S::kSolver,
       .solver_group = true,
       .ref = RunMember<double>([](RunParams& p) -> double& { return p.dt_max_factor; }),
       .fast = [](RunParams& p, bool) { p.dt_max_factor = kFastDtMaxFactor; }},
      {.key = "continued_dt_factor",
       .cli = "--continued-dt-factor",
       .help = "(fast) With --coarse-levels: the first relaxation at epsilon of each grid "
               "continued from a relaxed coarser one starts at dt = this times h, capped at "
               "--dt-max-factor h, instead of ramping up from --dt-factor h (0: the ramp; "
               "--fast uses 8, the largest dt, since 2026-11-28; 0 before)",
       .unit = "h",
       .scope = S::kSolver,
       .solver_group = true,
       .ref = RunMember<double>([](RunParams& p) -> double& { return p.continued_dt_factor; }),
       .range = {0.0, 1e6, true, true},
       .accepted = "0 (off) <= F <= 1e6",
       .fast = [](RunParams& p, bool) { p.continued_dt_factor = kFastContinuedDtFactor; },
       .optional_in_json = true},  // absent before 2026-11-27: off
      {.key = "settle_tol",
       .cli = "--settle-tol",
       .help = "Also end each relaxation at epsilon once its diffuse area and sharp volume "
               "fraction have settled: their last two changes shrank and the geometric tail they "
               "predict is below this (relative to the area; absolute for the volume fraction). "
               "A steady drift, such as a slow pinch-off, never settles (0: off, the paper's "
               "rule alone; --fast used 1e-5 before 2026-11-27)",
       .unit = "",
       .scope = S::kSolver,
       .solver_group = true,
       .ref = RunMember<double>([](RunParams& p) -> double& { return p.settle_tol; }),
       .range = {0.0, 1.0, true, false},
       .accepted = "0 (off) <= T < 1",
       .optional_in_json = true},  // absent before 2026-11-25: off
      {.key = "equilibrium_tol",
       .cli = "--equilibrium-tol",
       .help = "(fast) End each relaxation at epsilon once the equilibrium residual (the "
               "spread of the local H that the chemical potential still drives, in the units "
               "of H; report.json's equilibrium_residual) is at most this, instead of the --stop "
               "rule (0: off, the paper's rule; --fast uses 1e-3 at --grid 128, times "
               "(128/N)^2 at N; the coarser grids of a coarse-to-fine run end at it too, or "
               "once settled)",
       .unit = "1/unit cell",
       .scope = S::kSolver,
       .solver_group = true,
       .ref = RunMember<double>([](RunParams& p) -> double& { return p.equilibrium_tol; }),
       .range = {0.0, 1e3, true, false},
       .accepted = "0 (off) <= T < 1000",
       .fast = [](RunParams& p, bool) { p.equilibrium_tol = fast_equilibrium_tol(p.grid); },
       .optional_in_json = true},  // absent before 2026-11-27: off
      {.key = "anderson_depth",
       .cli = "--anderson-depth",
       .help = "(fast) Anderson acceleration of the late time steps: once a relaxation that "
               "ends on --equilibrium-tol steps at its largest dt, mix each step's field with "
               "the last M steps, which speeds up the slow geometric modes (0: off, the "
               "paper's plain steps; --fast uses 3)",
       .unit = "steps",
       .scope = S::kSolver,
       .solver_group = true,
       .ref = RunMember<int>([](RunParams& p) -> int& { return p.anderson_depth; }),
       .range = closed(0, 8),
       .accepted = "0 (off) <= M <= 8",
       .fast = [](RunParams& p, bool) { p.anderson_depth = kFastAndersonDepth; },
       .optional_in_json = true},  // absent before 2026-11-27: off
      {.key = "max_vcycles",
       .cli = "--max-vcycles",
       .help = "Limit on V-cycles per time step",
       .unit = "V-cycles",
       .scope = S::kSolver,
       .solver_group = true,
       .ref = RunMember<int>([](RunParams& p) -> int& { return p.solver.max_vcycles; }),
       .range = at_least(1),
       .accepted = ">= 1"},
      {.key = "pre_sweeps",
       .cli = "--pre-sweeps",
       .help = "Presmoothing sweeps (beta)",
       .unit = "sweeps",
       .scope = S::kSolver,
       .solver_group = true,
       .ref = RunMember<int>([](RunParams& p) -> int& { return p.solver.fas.pre_sweeps; }),
       .range = closed(0, 50),
       .accepted = "0..50"},
      {.key = "post_sweeps",
       .cli = "--post-sweeps",
       .help = "Postsmoothing sweeps (beta)",
       .unit = "sweeps",
       .scope = S::kSolver,
       .solver_group = true,
       .ref = RunMember<int>([](RunParams& p) -> int& { return p.solver.fas.post_sweeps; }),
       .range = closed(0, 50),
       .accepted = "0..50"},
      {.key = "prerelax_steps",
       .cli = "--prerelax-steps",
       .help = "Step 3: steps at the wide epsilon",
       .unit = "time steps",
       .scope = S::kSolver,
       .solver_group = true,
       .ref = RunMember<int>([](RunParams& p) -> int& { return p.prerelax_steps; }),
       .range = at_least(0),
       .accepted = ">= 0"},
      {.key = "prerelax_epsilon_factor",
       .cli = "--prerelax-epsilon-factor",
       .help = "Step 3: wide epsilon = factor * epsilon",
       .unit = "epsilon",
       .scope = S::kSolver,
       .solver_group = true,
       .ref = RunMember<double>([](RunParams& p) -> double& { return p.prerelax_epsilon_factor; }),
       .range = {0.0, 1000.0, false, true},
       .accepted = "0 < F <= 1000"},
      {.key = "bisection_tol",
       .cli = "--bisection-tol",
       .help = "Step 4: bisection tolerance",
       .unit = "",
       .scope = S::kSolver,
       .solver_group = true,
       .ref = RunMember<double>([](RunParams& p) -> double& { return p.bisection_tol; }),
       .range = above(0.0),
       .accepted = "> 0"},
      {.key = "bisection_max_it",
       .cli = "--bisection-max-it",
       .help = "Step 4: bisection iterations",
       .unit = "iterations",
       .scope = S::kSolver,
       .solver_group = true,
       .ref = RunMember<int>([](RunParams& p) -> int& { return p.bisection_max_it; }),
       .range = at_least(1),
       .accepted = ">= 1"},
      {.key = "max_volume_corrections",
       .cli = "--max-volume-corrections",
       .help = "--constrain volume: limit on mass corrections (each one a relaxation)",
       .unit = "corrections",
       .scope = S::kSolver,
       .solver_group = true,
       .ref = RunMember<int>([](RunParams& p) -> int& { return p.max_volume_corrections; }),
       .range = closed(0, 100),
       .accepted = "0..100"},
      {.key = "parallel_distances",
       .cli = "--parallel-distances",
       .help = "Distances l/a (comma-separated, each 0 < l < 0.25 cell units; '' none, the "
               "default) of the parallel surfaces whose areas and volumes report.json's "
               "parallel_surfaces lists beside Steiner's formula; a list (or --lipid-length) "
               "also measures the channel radii (several solves' time at 128^3)",
       .unit = "unit cell",
       .scope = S::kSolver,
       .solver_group = false,
       .ref = RunMember<std::string>(
           [](RunParams& p) -> std::string& { return p.parallel_distances; }),
       .optional_in_json = true},  // absent before the cell geometry: the default, none
      {.key = "lipid_length",
       .cli = "--lipid-length",
       .help = "Lipid length l (nm; 0: off): report.json's lipid gives the lattice parameter "
               "at which a bilayer of lipids of this length on both sides of the surface fills "
               "--lipid-fraction of the cell",
       .unit = "nm",
       .scope = S::kSolver,
       .solver_group = false,
       .ref = RunMember<double>([](RunParams& p) -> double& { return p.lipid_length; }),
       .range = {0.0, 1e6, true, false},
       .accepted = "0 (off) <= L < 1e6",
       .optional_in_json = true},
      {.key = "lipid_fraction",
       .cli = "--lipid-fraction",
       .help = "Lipid volume fraction phi_L of the lipid relation (with --lipid-length)",
       .unit = "",
       .scope = S::kSolver,
       .solver_group = false,
       .ref = RunMember<double>([](RunParams& p) -> double& { return p.lipid_fraction; }),
       .range = {0.0, 1.0, true, false},
       .accepted = "0 <= F < 1",
       .optional_in_json = true},
      {.key = "distance_field",
       .cli = "--distance-field",
       .help = "Add the array `distance` to the run's field file: the signed distance to the "
               "phi = 1/2 surface (cell units, > 0 in phase 1) that the tanh profile encodes, "
               "2 sqrt(2) epsilon atanh(2 phi - 1)",
       .unit = "",
       .scope = S::kSolver,
       .solver_group = false,
       .ref = RunMember<bool>([](RunParams& p) -> bool& { return p.distance_field; }),
       .optional_in_json = true},  // absent before it existed: false
      // Parameters a checkpoint or sweep.json carries that the command line does not set.
      {.key = "noise_amplitude",
       .cli = "",
       .help = "Amplitude of the noise surface's random field",
       .unit = "",
       .scope = S::kInternal,
       .solver_group = false,
       .ref = RunMember<double>([](RunParams& p) -> double& { return p.noise_amplitude; }),
       .range = at_least(0.0),
       .accepted = "finite, >= 0"},
      {.key = "coarsest_max_sweeps",
       .cli = "",
       .help = "Sweeps that solve the coarsest grid at most",
       .unit = "sweeps",
       .scope = S::kInternal,
       .solver_group = false,
       .ref = RunMember<int>([](RunParams& p) -> int& { return p.solver.fas.coarsest_max_sweeps; }),
       .range = at_least(1),
       .accepted = ">= 1"},
      {.key = "coarsest_reduction",
       .cli = "",
       .help = "Defect reduction that counts as solved on the coarsest grid",
       .unit = "",
       .scope = S::kInternal,
       .solver_group = false,
       .ref = RunMember<double>(
           [](RunParams& p) -> double& { return p.solver.fas.coarsest_reduction; }),
       .range = open(0.0, 1.0),
       .accepted = "0 < R < 1"},
  };
  return t;
}

}  // namespace

std::string RunOption::name() const {
  const std::string c = cli;
  if (c.empty()) return key;
  return c.substr(0, c.find(','));
}

std::span<const RunOption> run_option_table() { return table(); }

const RunOption* find_run_option(const std::string& key) {
  for (const RunOption& o : table())
    if (key == o.key) return &o;
  return nullptr;
}

RunOptionValue run_option_value(const RunOption& o, const RunParams& p) {
  // The members are read through the same accessors that write them; nothing is changed.
  RunParams& q = const_cast<RunParams&>(p);
  return std::visit(
      [&](const auto& ref) -> RunOptionValue {
        using R = std::decay_t<decltype(ref)>;
        if constexpr (std::is_same_v<R, RunChoice>) {
          return std::string(ref.names.at(ref.get(p)));
        } else {
          const auto& v = ref(q);
          using T = std::decay_t<decltype(v)>;
          if constexpr (std::is_same_v<T, int>)
            return static_cast<long long>(v);
          else
            return v;
        }
      },
      o.ref);
}

bool set_run_choice(const RunOption& o, RunParams& p, const std::string& name) {
  const auto* c = std::get_if<RunChoice>(&o.ref);
  if (c == nullptr) return false;
  for (std::size_t i = 0; i < c->names.size(); ++i)
    if (name == c->names[i]) {
      c->set(p, int(i));
      return true;
    }
  return false;
}

std::string run_choice_names(const RunOption& o) {
  std::string out;
  if (const auto* c = std::get_if<RunChoice>(&o.ref))
    for (const char* n : c->names) out += (out.empty() ? "" : ", ") + std::string(n);
  return out;
}

const RunOption* changed_run_option(const RunParams& mine, const RunParams& saved,
                                    const std::function<bool(const RunOption&)>& given,
                                    std::span<const RunOption> table) {
  for (const RunOption& o : table)
    if (given(o) && run_option_value(o, mine) != run_option_value(o, saved)) return &o;
  return nullptr;
}

}  // namespace cmcsurf
