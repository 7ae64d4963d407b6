#include "schema/report_schema.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace cmcsurf {

namespace {

constexpr PageTable kPage = PageTable::kKeyNumbers;

// The formats of the summaries and tables differ from the page's where they print fewer
// digits; each is written once, here.
const std::vector<ReportKey> kReportKeys = {
    // The run page's "Key numbers", in its order.
    {.key = "surface",
     .label = "surface",
     .help = "the surface's name (cmcsurf surfaces)",
     .page = kPage},
    {.key = "grid",
     .label = "grid N",
     .help = "cells per edge of the unit cell",
     .format = "{}",
     .page = kPage},
    {.key = "epsilon",
     .label = "ε",
     .help = "interface width of the phase field",
     .format = "{:.4g}",
     .page = kPage},
    {.key = "volume_fraction_target",
     .label = "target volume fraction α",
     .help = "the volume fraction asked for (null: a surface without one)",
     .format = "{:.6g}",
     .page = kPage,
     .sweep_page = {"α", "{:.4g}"}},
    {.key = "volume_fraction",
     .label = "volume fraction (sharp)",
     .help = "volume fraction of phi > 1/2: the 1/2 iso-surface of the piecewise-linear "
             "interpolant of the cell-centre values with its O(h^2) curvature bias removed "
             "(docs/volume.md)",
     .convention = true,
     .format = "{:.6f}",
     .page = kPage,
     .summary = "{:.5f}",
     .sweep_page = {"V", "{:.4f}"}},
    {.key = "area",
     .label = "area (sharp)",
     .help = "area of the phi = 1/2 surface: the zero set of the piecewise-linear interpolant of "
             "psi = atanh(2 phi - 1), second order in h (docs/method.md, sharp measures)",
     .convention = true,
     .format = "{:.6f}",
     .page = kPage,
     .error_key = "area_error",
     .summary = "{:.6f}",
     .member_line = "{:.5f}",
     .sweep_page = {"area", "{:.5f}"}},
    {.key = "mean_curvature",
     .label = "mean curvature H (sharp)",
     .help = "mean curvature of the phi = 1/2 surface, area-weighted average of the local H = "
             "-div(grad psi/|grad psi|)/2 on it; positive when phase 1 is convex (1/r for a ball)",
     .convention = true,
     .format = "{:+.6f}",
     .page = kPage,
     .error_key = "mean_curvature_error",
     .summary = "{:.5f}",
     .member_line = "{:+.4f}",
     .sweep_page = {"H", "{:+.5f}"}},
    {.key = "mean_curvature_mu",
     .label = "H from μ",
     .help = "mu/2 = 3 sqrt(2) nu / eps with nu = W'(phi) - eps^2 Lap phi, |grad phi|^2-weighted "
             "(Gibbs-Thomson; the paper's mu/3 is 2/3 of it, see docs/method.md)",
     .convention = true,
     .format = "{:+.6f}",
     .page = kPage,
     .summary = "{:.5f}"},
    {.key = "mean_curvature_std",
     .label = "local H std (relaxed)",
     .help = "standard deviation of the local H over the relaxed surface",
     .format = "{:.4g}",
     .page = kPage,
     .summary = "{:.4g}",
     .member_line = "{:.3g}",
     .sweep_page = {"H std", "{:.3g}"}},
    {.key = "nodal_mean_curvature",
     .label = "nodal H",
     .help = "H of the nodal surface at the same volume fraction",
     .format = "{:+.6f}",
     .page = kPage},
    {.key = "nodal_mean_curvature_std",
     .label = "local H std (nodal)",
     .help = "standard deviation of the local H over the nodal surface",
     .format = "{:.4g}",
     .page = kPage,
     .summary = "{:.4g}",
     .member_line = "{:.3g}",
     .sweep_page = {"nodal H std", "{:.3g}"}},
    {.key = "nodal_std_ratio",
     .label = "nodal / relaxed H std",
     .help = "nodal_mean_curvature_std / mean_curvature_std",
     .format = "{:.3g}",
     .page = kPage,
     .sweep_page = {"std ratio", "{:.3g}"}},
    {.key = "nodal_area_excess",
     .label = "nodal area excess",
     .help = "nodal_area / area - 1",
     .format = "{:+.4%}",
     .page = kPage,
     .member_line = "{:+.3%}",
     .sweep_page = {"nodal area excess", "{:+.3%}"}},
    {.key = "area_diffuse",
     .label = "area (diffuse, App. B)",
     .help = "Appendix B: 6 sqrt(2) eps sum |grad phi|^2 h^3 over the diffuse layer",
     .convention = true,
     .format = "{:.6f}",
     .page = kPage,
     .summary = "{:.6f}"},
    {.key = "mean_curvature_diffuse",
     .label = "H (diffuse, App. B)",
     .help = "Appendix B estimator, |grad phi|^2-weighted over the diffuse layer",
     .convention = true,
     .format = "{:+.6f}",
     .page = kPage,
     .summary = "{:.5f}"},
    {.key = "steps",
     .label = "time steps",
     .help = "relaxation steps at epsilon",
     .format = "{}",
     .page = kPage,
     .member_line = "{}",
     .sweep_page = {"steps", "{:.0f}"}},
    {.key = "vcycles",
     .label = "V-cycles",
     .help = "V-cycles over all steps",
     .format = "{}",
     .page = kPage},
    {.key = "vcycles_per_step",
     .label = "V-cycles per step",
     .help = "vcycles over all time steps, coarse and pre-relaxation ones included",
     .format = "{:.3g}",
     .page = kPage,
     .summary = "{:.2f}"},
    {.key = "converged",
     .label = "converged",
     .help = "the stop rule was met before max_steps",
     .page = kPage},
    {.key = "stop_reason",
     .label = "stop reason",
     .help = "the rule that ended the relaxation (area, phi, equilibrium, settled, max-steps)",
     .page = kPage},
    {.key = "wall_seconds",
     .label = "solve (s)",
     .unit = "s",
     .help = "wall time of the solve: steps 1-6, corrections and continuation",
     .format = "{:.3g}",
     .page = kPage,
     .timing = true,
     .summary = "{:.2f}",
     .member_line = "{:.1f}"},
    {.key = "measure_seconds",
     .label = "measures (s)",
     .unit = "s",
     .help = "wall time of the final field's sharp measures",
     .format = "{:.3g}",
     .page = kPage,
     .timing = true,
     .summary = "{:.2f}"},
    {.key = "quality_seconds",
     .label = "quality stage (s)",
     .unit = "s",
     .help = "wall time of the comparison with the nodal surface",
     .format = "{:.3g}",
     .page = kPage,
     .timing = true,
     .summary = "{:.2f}"},
    {.key = "properties_seconds",
     .label = "properties stage (s)",
     .unit = "s",
     .help = "wall time of --properties",
     .format = "{:.3g}",
     .page = kPage,
     .timing = true},
    {.key = "youngs_picture_seconds",
     .label = "Young's modulus picture (s)",
     .unit = "s",
     .help = "wall time of youngs_modulus.png",
     .format = "{:.3g}",
     .page = kPage,
     .timing = true},
    {.key = "preview_seconds",
     .label = "preview stage (s)",
     .unit = "s",
     .help = "wall time of preview.png's picture",
     .format = "{:.3g}",
     .page = kPage,
     .timing = true},
    {.key = "page_seconds",
     .label = "report page's meshes (s)",
     .unit = "s",
     .help = "wall time of report.html's meshes",
     .format = "{:.3g}",
     .page = kPage,
     .timing = true},
    {.key = "write_seconds",
     .label = "writing the files (s)",
     .unit = "s",
     .help = "wall time of writing the folder (report.json itself aside)",
     .format = "{:.3g}",
     .page = kPage,
     .timing = true},
    {.key = "version",
     .label = "cmcsurf version",
     .help = "the version that wrote the report",
     .page = kPage},

    // sweep.csv's leading columns that the page does not show.
    {.key = "area_error",
     .label = "area error",
     .help = "Richardson estimate |A_h - A_2h|/3 with A_2h from psi averaged to N/2",
     .convention = true},
    {.key = "mean_curvature_error",
     .label = "H error",
     .help = "Richardson estimate of the mean curvature's error (null: not computed)"},
    {.key = "area_iso", .label = "area (iso)", .help = "alias of area"},
    {.key = "nodal_area",
     .label = "nodal area",
     .help = "area of the nodal surface at the same volume fraction"},
    {.key = "nodal_area_iso", .label = "nodal area (iso)", .help = "alias of nodal_area"},
    {.key = "nodal_area_excess_iso",
     .label = "nodal area excess (iso)",
     .help = "alias of nodal_area_excess"},

    // The other timings.
    {.key = "solver_seconds",
     .label = "V-cycles (s)",
     .unit = "s",
     .help = "wall time inside the V-cycles",
     .timing = true},
    {.key = "volume_seconds",
     .label = "volume corrections (s)",
     .unit = "s",
     .help = "wall time of the volume constraint's corrections",
     .timing = true},
    {.key = "seconds_per_vcycle",
     .label = "time per V-cycle (s)",
     .unit = "s",
     .help = "solver_seconds / vcycles",
     .timing = true,
     .summary = "{:.2f}"},  // in ms there
    {.key = "surface_mesh_seconds",
     .label = "surface mesh (s)",
     .unit = "s",
     .help = "wall time of --mesh's surface mesh",
     .timing = true},
    {.key = "checkpoint_seconds",
     .label = "checkpoints (s)",
     .unit = "s",
     .help = "wall time of writing checkpoints",
     .timing = true},
    {.key = "checkpoints_written",
     .label = "checkpoints written",
     .help = "checkpoints this invocation wrote",
     .timing = true},
    {.key = "resumed_from_step",
     .label = "resumed from step",
     .help = "the checkpoint's step this invocation resumed from",
     .timing = true},
    {.key = "peak_memory_bytes",
     .label = "peak memory",
     .unit = "bytes",
     .help = "peak resident memory of the process so far",
     .timing = true},
    {.key = "peak_memory_bytes_per_cell",
     .label = "peak memory per cell",
     .unit = "bytes",
     .help = "peak_memory_bytes / grid^3",
     .timing = true},

    // The other keys of a run's report.json.
    {.key = "build",
     .label = "build",
     .help = "the build that wrote the report: version, commit, compiler, flags"},
    {.key = "h", .label = "cell size h", .help = "1 / grid"},
    {.key = "dt", .label = "time step", .help = "dt_factor h"},
    {.key = "dt_max",
     .label = "largest time step",
     .help = "the largest step taken (adaptive steps)"},
    {.key = "prerelax_steps",
     .label = "pre-relaxation steps",
     .help = "steps at the wide epsilon (step 3)"},
    {.key = "coarse_steps",
     .label = "coarse steps",
     .help = "steps on the continuation's coarser grids"},
    {.key = "volume_steps", .label = "volume steps", .help = "steps after the mass corrections"},
    {.key = "unconverged_steps",
     .label = "unconverged steps",
     .help = "steps whose V-cycles hit max_vcycles"},
    {.key = "time", .label = "model time", .help = "model time at the end"},
    {.key = "final_d_area", .label = "last dA", .help = "the last step's change of area"},
    {.key = "final_d_phi", .label = "last d phi", .help = "the last step's ||phi^{n+1} - phi^n||"},
    {.key = "total_mean_curvature",
     .label = "total H",
     .help = "integral of H dA over the sharp surface"},
    {.key = "total_mean_curvature_diffuse",
     .label = "total H (diffuse)",
     .help = "Appendix B's integral of H dA"},
    {.key = "mean_curvature_local_mean",
     .label = "mean of local H",
     .help = "unweighted mean of the samples' H"},
    {.key = "mean_curvature_mu_gap",
     .label = "H from μ - H",
     .help = "mean_curvature_mu - mean_curvature",
     .convention = true},
    {.key = "volume_fraction_cells",
     .label = "volume fraction (cells)",
     .help = "fraction of cells with phi > 1/2",
     .convention = true},
    {.key = "mass", .label = "mass", .help = "mean of phi", .convention = true},
    {.key = "energy", .label = "energy", .help = "Ginzburg-Landau energy of the final field"},
    {.key = "equilibrium_residual",
     .label = "equilibrium residual",
     .help = "spread of the chemical potential on the interface (--equilibrium-tol's measure)"},
    {.key = "euler_characteristic",
     .label = "Euler characteristic",
     .help = "of phase 1 (phi > 1/2) as the union of its closed voxels in the periodic cell: "
             "tells which member of a family a run found near a topology change (docs/families.md)",
     .convention = true},
    {.key = "euler_characteristic_phase1",
     .label = "Euler characteristic (phase 1)",
     .help = "= euler_characteristic (phase 1, phi > 1/2)",
     .convention = true},
    {.key = "euler_characteristic_phase2",
     .label = "Euler characteristic (phase 2)",
     .help = "of phase 2 (phi < 1/2), as closed voxels the same way",
     .convention = true},
    {.key = "euler_characteristic_surface",
     .label = "Euler characteristic (surface)",
     .help = "of the phi = 1/2 surface per computed cell: phase1 + phase2 (= 2 chi(phase 1) for a "
             "resolved surface; P -4, D -16, G -8 at 1/2)",
     .convention = true},
    {.key = "euler_characteristic_start",
     .label = "Euler characteristic (start)",
     .help = "the same of the nodal start phi^0 (step 1's field): the family's topology; "
             "topology_changed: the run ended on a member of another one",
     .convention = true},
    {.key = "topology_changed",
     .label = "topology changed",
     .help = "the run ended on another family's member"},
    {.key = "genus",
     .label = "genus",
     .help = "1 - euler_characteristic: the surface's genus per unit cell when both phases are "
             "connected (P 3, G 5, D 9; a ball 0)",
     .convention = true},
    {.key = "genus_surface",
     .label = "genus (surface)",
     .help = "genus of each connected piece of the surface, 1 - chi_surface / (2 "
             "surface_components): their mean when the pieces differ",
     .convention = true},
    {.key = "components_phase1",
     .label = "components (phase 1)",
     .help = "connected components of phase 1 on the 3-torus (26-connected voxels); null on a "
             "decomposed grid above 128^3",
     .convention = true},
    {.key = "components_phase2",
     .label = "components (phase 2)",
     .help = "connected components of phase 2"},
    {.key = "surface_components",
     .label = "surface components",
     .help = "(phase 1, phase 2) component pairs that touch: the surface's connected pieces (a "
             "pair meeting on two sheets counts once)",
     .convention = true},
    {.key = "homogeneity_index",
     .label = "homogeneity index",
     .help = "Gamma = A^(3/2) / (2 pi |chi_surface|)^(1/2), area A per cell of volume 1 (Hyde "
             "1989; any cell of the lattice gives the same)",
     .convention = true},
    {.key = "gaussian_curvature_integral",
     .label = "integral of K",
     .help = "integral of K dA over the sharp surface, K from grad psi and its Hessian like H",
     .convention = true},
    {.key = "gauss_bonnet_error",
     .label = "Gauss-Bonnet error",
     .help = "gaussian_curvature_integral / (2 pi chi_surface) - 1",
     .convention = true},
    {.key = "mean_gaussian_curvature",
     .label = "mean K",
     .help = "gaussian_curvature_integral / area: <K> a^2",
     .convention = true},
    {.key = "willmore_energy",
     .label = "Willmore energy",
     .help = "integral of H^2 dA over the sharp surface",
     .convention = true},
    {.key = "initial", .label = "initial measures", .help = "the measures of phi^0 (an object)"},
    {.key = "crystallographic_cell",
     .label = "crystallographic cell",
     .help = "the space group's cubic cell the literature states numbers in (P Im-3m, D Pn-3m "
             "with a/2: 8 per computed cell, G Ia-3d); lattice_parameter over the computed a; "
             "area per cell in its own units, chi per cell, mean_curvature = H a_c, "
             "mean_gaussian_curvature = <K> a_c^2 (docs/science.md)",
     .convention = true},
    {.key = "bisection",
     .label = "bisection",
     .help = "steps 4-5: beta, v_ave, iterations, mass_before_shift"},
    {.key = "constrain", .label = "constraint", .help = "--constrain: volume, mass or components"},
    {.key = "constrain_note",
     .label = "constraint note",
     .help = "what the constraint did, when it was not volume"},
    {.key = "volume_corrections",
     .label = "volume corrections",
     .help = "mass corrections of --constrain volume"},
    {.key = "volume_iterates",
     .label = "volume iterates",
     .help = "--constrain volume: (mass, volume_fraction) after step 6 and after each mass "
             "correction and relaxation",
     .convention = true},
    {.key = "volume_converged",
     .label = "volume converged",
     .help = "the volume fraction is within --volume-tol"},
    {.key = "interfaces",
     .label = "interfaces",
     .help = "one entry per component of the phase with more components (phase 1 when both have "
             "one): its boundary's area, mean_curvature, mean_curvature_std, "
             "gaussian_curvature_integral and euler_characteristic (2 chi of the component) and "
             "the component's enclosed_volume; the surface's connected pieces when each such "
             "component touches one component of the other phase (docs/science.md, double "
             "structures)",
     .convention = true},
    {.key = "component_volume_targets",
     .label = "component volume targets",
     .help = "--constrain components: the volume each component of phase 1 holds (its seed's, "
             "scaled to sum to alpha); component_volumes: the final sharp volumes",
     .convention = true},
    {.key = "component_volumes",
     .label = "component volumes",
     .help = "the components' final sharp volumes"},
    {.key = "warnings",
     .label = "warnings",
     .help = "what the command line printed as warnings: the result's topology differs from its "
             "seed's, or the seed's components share one volume constraint",
     .convention = true},
    // The cell geometry (with --parallel-distances or --lipid-length; its conventions are
    // written only then, by io/run_report.cpp).
    {.key = "channel_radius",
     .label = "channel radius",
     .help = "per phase: the radius of the largest ball inside the phase that contains each "
             "cell, statistics in units of the computed cell (docs/science.md)"},
    {.key = "parallel_surfaces",
     .label = "parallel surfaces",
     .help = "for each --parallel-distances l and side: the area of {d = l} and the volume "
             "between the surface and it, beside Steiner's formula"},
    {.key = "lipid",
     .label = "lipid relation",
     .help = "--lipid-length and --lipid-fraction: l/a and the lattice parameter they imply"},
    {.key = "geometry_seconds",
     .label = "cell geometry (s)",
     .unit = "s",
     .help = "wall time of the cell geometry (part of measure_seconds)",
     .timing = true},
    {.key = "balanced",
     .label = "balanced",
     .help = "the nodal surface's two sides are congruent (null: no formula)"},
    {.key = "threads", .label = "threads", .help = "OpenMP threads of rank 0"},
    {.key = "threads_per_rank",
     .label = "threads per rank",
     .help = "every rank's OpenMP threads (under mpirun)"},
    {.key = "parameters",
     .label = "parameters",
     .help = "every run option by its key (pipeline/run_schema.cpp)"},
    {.key = "conventions", .label = "conventions", .help = "what the keys mean, a sentence each"},
    {.key = "nodal_level",
     .label = "nodal level",
     .help = "the level c of the nodal surface {F = c} at alpha"},
    {.key = "nodal_volume_fraction",
     .label = "nodal volume fraction",
     .help = "sharp volume fraction of {F > c}"},
    {.key = "nodal_area_diffuse",
     .label = "nodal area (diffuse)",
     .help = "Appendix B's area of the nodal profile"},
    {.key = "nodal_area_tanh",
     .label = "nodal area (tanh)",
     .help = "the earlier name of nodal_area_diffuse"},
    {.key = "nodal_relax_steps",
     .label = "nodal relaxation steps",
     .help = "0: the nodal surface is not relaxed"},
    {.key = "nodal_mean_curvature_diffuse",
     .label = "nodal H (diffuse)",
     .help = "Appendix B's H of the nodal profile"},
    {.key = "nodal_mean_curvature_local_mean",
     .label = "nodal mean of local H",
     .help = "unweighted mean of the nodal samples' H"},
    {.key = "mpi_ranks", .label = "MPI ranks", .help = "processes of the run"},
    {.key = "process_grid",
     .label = "process grid",
     .help = "the decomposition's processes per axis"},
    {.key = "mpi_rank0",
     .label = "rank 0's communication",
     .help = "rank 0's halo and gather counters"},
    {.key = "member", .label = "sweep member", .help = "the member's name (its folder)"},
    {.key = "started_from", .label = "started from", .help = "nodal, or the member it continued"},
    {.key = "sweep_group",
     .label = "sweep group",
     .help = "the group of processes that ran the member"},
    {.key = "properties",
     .label = "properties",
     .help = "--properties: the solid's stiffness and conductivity"},
    {.key = "checkpoint",
     .label = "checkpoint",
     .help = "an interrupted run's checkpoint: file, step, stage, grid, signal, "
             "anderson_columns (the mixing history it carries)"},
    {.key = "resume",
     .label = "resume command",
     .help = "the command that resumes an interrupted run"},
    {.key = "peak_memory_bytes_per_rank",
     .label = "peak memory per rank",
     .unit = "bytes",
     .help = "every rank's peak resident memory (under mpirun)",
     .timing = true},
    {.key = "peak_memory_bytes_max_rank",
     .label = "peak memory, largest rank",
     .unit = "bytes",
     .help = "the largest of peak_memory_bytes_per_rank",
     .timing = true},
};

const std::vector<HistoryColumnInfo> kHistoryColumns = {
    {HistoryColumn::kStep, "step", HistoryType::kInt, "{}", "",
     "time steps so far, pre-relaxation included"},
    {HistoryColumn::kStage, "stage", HistoryType::kText, "{}", "",
     "prerelax, relax or volume; \"@N\" for each coarser grid of the continuation it was "
     "taken on (relax@32)"},
    {HistoryColumn::kTime, "time", HistoryType::kNumber, "{:.17g}", "", "model time"},
    {HistoryColumn::kArea, "area", HistoryType::kNumber, "{:.17g}", "",
     "diffuse area at the stage's epsilon"},
    {HistoryColumn::kDArea, "d_area", HistoryType::kNumber, "{:.17g}", "",
     "the step's change of area"},
    {HistoryColumn::kDPhi, "d_phi", HistoryType::kNumber, "{:.17g}", "", "||phi^{n+1} - phi^n||"},
    {HistoryColumn::kEnergy, "energy", HistoryType::kNumber, "{:.17g}", "",
     "Ginzburg-Landau energy"},
    {HistoryColumn::kMass, "mass", HistoryType::kNumber, "{:.17g}", "", "mean of phi"},
    {HistoryColumn::kVcycles, "vcycles", HistoryType::kInt, "{}", "", "V-cycles of the step"},
    {HistoryColumn::kResidual, "residual", HistoryType::kNumber, "{:.6e}", "",
     "the last V-cycle's residual"},
    {HistoryColumn::kElapsed, "elapsed", HistoryType::kNumber, "{:.6f}", "s",
     "wall seconds since the run started", true},
    {HistoryColumn::kDt, "dt", HistoryType::kNumber, "{:.17g}", "", "the step's time step"},
    {HistoryColumn::kVolumeFraction, "volume_fraction", HistoryType::kNumber, "{:.17g}", "",
     "sharp volume fraction after the step"},
};

const std::vector<std::string_view> kSweepLeading = {"surface",
                                                     "volume_fraction_target",
                                                     "volume_fraction",
                                                     "area",
                                                     "area_error",
                                                     "mean_curvature",
                                                     "mean_curvature_error",
                                                     "mean_curvature_mu",
                                                     "mean_curvature_std",
                                                     "area_diffuse",
                                                     "mean_curvature_diffuse",
                                                     "area_iso",
                                                     "nodal_area",
                                                     "nodal_area_iso",
                                                     "nodal_mean_curvature",
                                                     "nodal_mean_curvature_std",
                                                     "nodal_std_ratio",
                                                     "nodal_area_excess",
                                                     "nodal_area_excess_iso"};

const std::vector<FamiliesColumn> kFamilies = {
    {"volume_fraction_target", {"alpha", "{:.2f}"}},
    {"volume_fraction", {"V (sharp)", "{:.4f}"}},
    {"area", {"area", "{:.4f}"}},
    {"area_diffuse", {"area (diffuse)", "{:.4f}"}},
    {"mean_curvature", {"H", "{:+.4f}"}},
    {"mean_curvature_diffuse", {"H (diffuse)", "{:+.4f}"}},
    {"mean_curvature_std", {"H std", "{:.4f}"}},
    {"nodal_mean_curvature", {"nodal H", "{:+.4f}"}},
    {"nodal_mean_curvature_std", {"nodal H std", "{:.3f}"}},
    {"nodal_std_ratio", {"std ratio", "{:.0f}"}},
    {"nodal_area_excess", {"nodal excess", "{:+.3%}"}},
    {"steps", {"steps", "{:.0f}"}},
    {"wall_seconds", {"s", "{:.1f}"}},
};

constexpr std::string_view kStageNames[] = {"prerelax", "relax", "volume"};

std::string_view page_name(PageTable t) { return t == PageTable::kKeyNumbers ? "key_numbers" : ""; }

std::string_view type_name(HistoryType t) {
  switch (t) {
    case HistoryType::kInt: return "int";
    case HistoryType::kText: return "str";
    case HistoryType::kNumber: return "float";
  }
  return "";
}

std::string str(std::string_view s) { return std::string(s); }

std::string history_names(std::string_view separator) {
  std::string out;
  for (const HistoryColumnInfo& c : kHistoryColumns) {
    if (!out.empty()) out += separator;
    out += c.name;
  }
  return out;
}

}  // namespace

const std::vector<ReportKey>& report_key_table() { return kReportKeys; }

const ReportKey& report_key(std::string_view key) {
  for (const ReportKey& k : kReportKeys)
    if (k.key == key) return k;
  throw std::logic_error(fmt::format("report key '{}' is not in report_key_table()", key));
}

std::vector<std::string> timing_report_keys() {
  std::vector<std::string> keys;
  for (const ReportKey& k : kReportKeys)
    if (k.timing) keys.push_back(str(k.key));
  std::sort(keys.begin(), keys.end());
  return keys;
}

std::string format_report_number(std::string_view format, double x) {
  if (format.size() > 2 && format.substr(format.size() - 2) == "%}") {
    std::string as_f(format.substr(0, format.size() - 2));
    as_f += "f}";
    std::string out = fmt::format(fmt::runtime(as_f), 100.0 * x);
    out += '%';
    return out;
  }
  return fmt::format(fmt::runtime(format), x);
}

std::string summary_number(std::string_view key, double x) {
  return format_report_number(report_key(key).summary, x);
}

std::string member_line_number(std::string_view key, double x) {
  return format_report_number(report_key(key).member_line, x);
}

std::string_view run_stage_name(RunStage s) { return kStageNames[int(s)]; }

std::optional<RunStage> parse_run_stage(std::string_view name) {
  for (int i = 0; i < 3; ++i)
    if (kStageNames[i] == name) return RunStage(i);
  return std::nullopt;
}

const std::vector<HistoryColumnInfo>& history_column_table() { return kHistoryColumns; }

std::string history_header() { return history_names(","); }

std::string history_column_list() { return history_names(", "); }

const std::vector<std::string_view>& sweep_leading_columns() { return kSweepLeading; }

const std::vector<FamiliesColumn>& families_table_columns() { return kFamilies; }

std::string report_schema_json() {
  nlohmann::ordered_json keys = nlohmann::ordered_json::array();
  for (const ReportKey& k : kReportKeys)
    keys.push_back(
        {{"key", k.key},
         {"label", k.label},
         {"unit", k.unit},
         {"help", k.help},
         {"convention", k.convention},
         {"format", k.format},
         {"page", page_name(k.page)},
         {"error_key", k.error_key},
         {"timing", k.timing},
         {"summary", k.summary},
         {"member_line", k.member_line},
         {"sweep_page", {{"header", k.sweep_page.header}, {"format", k.sweep_page.format}}}});
  nlohmann::ordered_json history = nlohmann::ordered_json::array();
  for (const HistoryColumnInfo& c : kHistoryColumns)
    history.push_back({{"name", c.name},
                       {"type", type_name(c.type)},
                       {"format", c.format},
                       {"unit", c.unit},
                       {"help", c.help},
                       {"timing", c.timing}});
  nlohmann::ordered_json families = nlohmann::ordered_json::array();
  for (const FamiliesColumn& c : kFamilies)
    families.push_back({{"key", c.key}, {"header", c.view.header}, {"format", c.view.format}});
  nlohmann::ordered_json out = {{"report_keys", keys},
                                {"history_columns", history},
                                {"stages", kStageNames},
                                {"sweep_leading_columns", kSweepLeading},
                                {"families_table", families}};
  return out.dump(1) + "\n";
}

}  // namespace cmcsurf
