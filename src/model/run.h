// The plain types of a run: what a user asked for (RunParams), what a run measured and returned
// (Measures, StepRecord, RunResult) and where it stands between two time steps (RunCursor,
// Checkpoint). io/ serialises them and pipeline/ fills them; they live below both so that
// io/ needs no part of the algorithm.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "cahn_hilliard/anderson.h"
#include "cahn_hilliard/time_step.h"
#include "grid/field.h"
#include "measure/components.h"
#include "measure/sharp_surface.h"
#include "model/cell_geometry.h"
#include "schema/report_schema.h"

namespace cmcsurf {

enum class StopRule { kArea, kPhi };

// What step 6 holds at alpha for nodal surfaces: the sharp volume fraction of {phi > 1/2}
// (Section 2.1's constraint; mass corrections after step 6, docs/volume.md) or the mass (the
// paper's Section 4.4 as printed). kComponents holds the sharp volume of each connected
// component of phase 1 at every step (pipeline/component_constraint.h): two networks in a
// matrix keep theirs, where one shared constraint lets them exchange volume.
enum class Constraint { kVolume, kMass, kComponents };
const char* constraint_name(Constraint c);

// The seed of a nodal surface: single (phase 1 = {F > c}, steps 1-5) or double (phase 1 =
// {|F| > c}: two networks in a matrix, seeded with the tanh profile at alpha; no pre-relaxation,
// whose wide layer would dissolve the thin matrix, and no steps 4-5).
enum class Structure { kSingle, kDouble };

struct RunParams {
  std::string surface = "G";
  double volume_fraction = 0.5;  // alpha, for nodal surfaces
  int grid = 128;  // epsilon = 1.28 h resolves the interface; --paper: kPaperGrid
  double epsilon = 0.01;
  double dt_factor = 0.5;  // dt = dt_factor * h
  StopRule stop = StopRule::kArea;
  double tol = 1e-6;
  int max_steps = 20000;
  SweepOrder smoother = SweepOrder::kRedBlack;
  double radius = 0.25;  // sphere
  std::uint64_t seed = 1;  // noise
  double noise_amplitude = 0.01;
  // Step 3: a few steps with a wider interface before the bisection.
  int prerelax_steps = 5;
  double prerelax_epsilon_factor = 5.0;
  // Step 4: bisection on beta.
  double bisection_tol = 1e-6;
  int bisection_max_it = 60;
  // After step 6 (kVolume): secant corrections of the mass until |V - alpha| <= volume_tol.
  Constraint constrain = Constraint::kVolume;
  double volume_tol = 1e-4;
  int max_volume_corrections = 8;
  StepSolverOptions solver;
  // Coarse-to-fine continuation (0: off; the fast mode chooses it): run on N/2^K first,
  // then interpolate and relax on each finer grid. Nodal surfaces only.
  int coarse_levels = 0;
  // Adaptive time steps (0: off; the fast mode chooses it): in each relaxation dt starts at
  // dt_factor h and doubles after every step whose V-cycles converged, up to dt_max_factor h;
  // a step that hits --max-vcycles halves it. The convex splitting is stable for any dt and
  // its fixed points do not depend on dt, so only the path to the equilibrium changes.
  double dt_max_factor = 0.0;
  // With coarse_levels > 0: the first relaxation at epsilon of a grid continued from a relaxed
  // coarser one starts at this times h (capped at dt_max_factor h) instead of dt_factor h
  // (0: dt_factor h, the ramp of every other relaxation).
  double continued_dt_factor = 0.0;
  // Settling (the fast mode's finishing rule, off when 0): a relaxation at epsilon also ends
  // when its diffuse area and its sharp volume fraction have settled: their last two changes
  // shrank and the geometric tail they predict is at most settle_tol (relative to the area;
  // absolute for the volume fraction; pipeline/continuation.h). A drift that does not shrink,
  // such as a slow pinch-off, never settles; the paper's stop rule still applies beside it.
  double settle_tol = 0.0;
  // With coarse_levels > 0: the relative V-cycle stop (StepSolverOptions::rtol) on the finest
  // grid only, which starts from the interpolated relaxed coarse field (0: solver.rtol there too).
  double mg_rtol_finest = 0.0;
  // The stop rule on the equilibrium itself (off when 0): a relaxation at epsilon ends when the
  // equilibrium residual (measure/measures.h: the spread of the local H that the chemical
  // potential still drives, in the units of H) is at most this, instead of the --stop rule.
  double equilibrium_tol = 0.0;
  // Anderson acceleration of the late steps (0: off): while a relaxation that ends on the
  // equilibrium rule steps at its largest dt, each step's field is mixed with the last
  // anderson_depth steps (cahn_hilliard/anderson.h), which speeds up the slow geometric modes.
  int anderson_depth = 0;
  // The user asked for the fast mode (the default; finish_run_params sets the options it chooses
  // above) or for the paper-faithful algorithm of Section 4.4 (`--paper`: fast off, kPaperGrid).
  bool fast = true;
  bool paper = false;
  Structure structure = Structure::kSingle;
  // The cell geometry of the final field (pipeline/cell_geometry.h; measured only when either
  // is given, since it costs several solves at 128^3): the parallel surfaces' distances l/a
  // ("" none), and a lipid length (nm; 0: off) with the lipid volume fraction whose lattice
  // parameter the lipid relation gives.
  std::string parallel_distances;
  double lipid_length = 0.0;
  double lipid_fraction = 0.0;
  // Write the profile's signed distance (RunResult::distance) beside phi in the field file.
  bool distance_field = false;

  double h() const { return 1.0 / grid; }
  double dt() const { return dt_factor * h(); }
};

// The measures reported for a field. area and mean_curvature are the surface's own (the
// sharp estimators of measure/sharp_surface.h); the *_diffuse ones are Appendix B's averages
// over the diffuse layer, in which the paper states its tables.
struct Measures {
  double area = 0.0;
  double area_error = 0.0;  // Richardson estimate; NaN where not computed (decomposed blocks)
  double mean_curvature = 0.0;
  double mean_curvature_error = 0.0;
  double mean_curvature_std = 0.0;     // spread of the local H over the surface
  double total_mean_curvature = 0.0;  // mean_curvature * area
  double area_diffuse = 0.0;
  double mean_curvature_diffuse = 0.0;
  double total_mean_curvature_diffuse = 0.0;  // as in Table 1
  double mean_curvature_mu = 0.0;
  double volume_fraction = 0.0;        // sharp: measure/sharp_volume.h
  double volume_fraction_cells = 0.0;  // fraction of cells with phi > 1/2
  double mass = 0.0;
  double energy = 0.0;
  double equilibrium_residual = 0.0;  // measure/measures.h: 0 at a steady state
  bool sharp = false;  // whether the sharp measures were taken (else they are 0)
  // Of phase 1 as closed voxels (measure/topology.h); with sharp. 1 - chi is the genus of the
  // surface per unit cell when both phases are connected: which member of a family a run found.
  std::int64_t euler_characteristic = 0;
  std::int64_t euler_characteristic_phase2 = 0;  // of phi < 1/2, the same way
  // Connected components of each phase and (phase 1, phase 2) component pairs that touch
  // (measure/topology.h's phase_components); -1 where not computed (a decomposed grid above
  // kComponentsGatherMaxN).
  std::int64_t components_phase1 = -1;
  std::int64_t components_phase2 = -1;
  std::int64_t surface_components = -1;
  // Of the sharp surface (measure/sharp_surface.h): integral K dA and integral H^2 dA.
  double gaussian_curvature_integral = 0.0;
  double willmore_energy = 0.0;
  // chi of the surface: chi(phase 1) + chi(phase 2) (each half of it when they agree).
  std::int64_t euler_characteristic_surface() const {
    return euler_characteristic + euler_characteristic_phase2;
  }
};

struct StepRecord {
  int step = 0;           // counts all time steps, pre-relaxation included
  RunStage stage = RunStage::kRelax;  // prerelax (step 3, at 5 eps), relax (step 6) or volume
                                      // (relaxations after the mass corrections of kVolume)
  // Coarse-to-fine continuation: the grids the step's run was carried up through, from the one
  // it was taken on ("relax@16@32" in history.csv: on 16, for a run on 64); empty on the
  // run's own grid.
  std::vector<int> coarse_grids;
  double time = 0.0;
  double dt = 0.0;        // of this step
  double area = 0.0;      // at the stage's epsilon
  double d_area = 0.0;    // A^{n+1} - A^n
  double d_phi = 0.0;     // ||phi^{n+1} - phi^n||
  double energy = 0.0;
  double mass = 0.0;
  double volume_fraction = 0.0;  // sharp (measure/sharp_volume.h), after the step
  int vcycles = 0;
  double residual = 0.0;
  double elapsed = 0.0;   // wall seconds since the run started
  // The equilibrium stop rule's residual after the step (measure/measures.h
  // equilibrium_residual); NaN where the rule did not run (--paper, a pre-relaxation, the
  // coarser grids of runs before late 2026-11-27, steps recorded before the column existed).
  double equilibrium_residual = std::numeric_limits<double>::quiet_NaN();
};

struct BisectionResult {
  double beta = 0.0;
  double v_ave = 0.0;
  int iterations = 0;
};

// One relaxed state of the volume constraint's secant iteration on the mass.
struct VolumeIterate {
  double mass = 0.0;
  double volume_fraction = 0.0;  // sharp, after the relaxation
  int steps = 0;                 // time steps of the relaxation that produced it
  bool relaxed = false;          // that relaxation met the stop rule
};

// What report.json compares: the components of each phase and the Euler characteristics.
struct PhaseTopology {
  std::int64_t components_phase1 = -1;
  std::int64_t components_phase2 = -1;
  std::int64_t euler_characteristic_phase1 = 0;
  std::int64_t euler_characteristic_phase2 = 0;
  bool operator==(const PhaseTopology&) const = default;
};

struct RunResult {
  Field phi;  // final field (ghost 2; this process's block under a decomposition)
  std::vector<StepRecord> history;
  int steps = 0;            // relaxation steps at epsilon (step 6 and the "volume" stage)
  int volume_steps = 0;     // of which after mass corrections (stage "volume")
  int prerelax_steps = 0;   // steps at 5 epsilon (step 3)
  int coarse_steps = 0;     // all steps on coarser grids (coarse_levels > 0)
  long vcycles = 0;         // over all steps
  int unconverged_steps = 0;  // steps whose V-cycles hit the limit before the tolerance
  bool converged = false;   // the stop rule was met before max_steps
  std::string stop_reason;
  std::optional<BisectionResult> bisection;  // nodal surfaces only
  double mass_before_shift = 0.0;
  // Volume constraint: whether it applied (nodal surfaces with Constraint::kVolume), the
  // iterates (the first is step 6's result, each later one a correction) and whether the last
  // is within volume_tol of alpha.
  bool volume_constrained = false;
  std::vector<VolumeIterate> volume_iterates;
  bool volume_converged = false;
  double volume_seconds = 0.0;  // wall time of the corrections
  Measures initial;         // phi^0 (after truncation for nodal surfaces), at epsilon
  Measures final;
  // chi of phase 1 of step 1's field (initial's): for run_cmc the nodal start, the family's
  // topology (pipeline/member_topology.h); set by run_cmc and run_cmc_from_field.
  std::optional<std::int64_t> euler_characteristic_start;
  double wall_seconds = 0.0;    // the solve: steps 1-6, corrections and continuation
  double solver_seconds = 0.0;  // inside the V-cycles
  double measure_seconds = 0.0;  // the sharp measures of the final field
  // Double structures (whole grids; empty otherwise). Constraint::kComponents: each
  // component's target volume and final sharp volume. The seed's topology (the field step 6
  // starts from), each connected piece of the final surface (measure/components.h) and the
  // warnings report.json lists and the command line prints.
  std::vector<double> component_volume_targets;
  std::vector<double> component_volumes;
  std::optional<PhaseTopology> seed_topology;
  std::vector<InterfaceMeasures> interfaces;
  std::vector<std::string> warnings;
  // Channel radii, parallel surfaces and the lipid relation of the final field (whole grids,
  // when asked for; its time is part of measure_seconds and its own geometry.seconds).
  std::optional<CellGeometry> geometry;
  // With RunParams::distance_field (whole grids): profile_distance of the final field.
  Field distance;
};

// What the final measures computed on the way, returned beside the result for the stages after
// the run (run_outputs): psi = atanh(2 phi - 1) of the final field (ghost 2; this process's
// block under a decomposition) and its surface's local mean curvature samples.
struct FinalFieldCache {
  Field psi;
  std::vector<CurvatureSample> samples;
};

// Where a run stands between two time steps, in the terms of Section 4.4's algorithm: with the
// fields of a Checkpoint, enough to continue it to the same bits.
struct RunCursor {
  int grid = 0;           // of the stage (N / 2^k during coarse-to-fine continuation)
  RunStage stage = RunStage::kRelax;  // prerelax (step 3), relax (step 6), volume (corrections)
  int stage_steps = 0;    // steps taken in the stage's loop so far
  double dt = 0.0;        // of the next step
  double area = 0.0;      // area at the stage's epsilon before the next step
  double volume = 0.0;    // "volume": the sharp volume fraction before the next step
  int correction = 0;     // "volume": the mass correction in progress (0-based)
  double slope = 1.0;     // "volume": the secant slope it used
};

// A run's whole state between two time steps (docs/reliability.md), apart from its
// parameters (RunParams, which the caller keeps): the position, the result so far (its phi on
// cursor.grid; this process's block under a decomposition), the stepper's carried fields and
// the Anderson mixer's history.
struct Checkpoint {
  RunCursor cursor;
  RunResult result;
  ChStepperState stepper;
  // The mixer of the relaxation in progress (none: no mixing there, or not carried).
  std::optional<AndersonState> anderson;
  // False for a checkpoint of a format before the mixer's (4, 5): a relaxation it continues
  // starts the mixing afresh and ends on the same surface, not on the same bits.
  bool anderson_carried = true;
  int step = 0;        // time steps taken, all stages
  double time = 0.0;   // model time
  bool last_step_converged = true;
  double elapsed = 0.0;  // wall seconds of the run so far
};

}  // namespace cmcsurf
