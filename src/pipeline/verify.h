// The paper's verification experiments (Sections 4.1-4.3, Table 1) as library calls, and the
// checks that decide whether they reproduce the paper (tolerances justified in
// docs/verification.md); the command line prints them beside the paper's numbers and fails
// when a check fails.
#pragma once

#include <string>
#include <vector>

#include "pipeline/cmc.h"

namespace cmcsurf {

// The grids of the experiments below: those run --grid takes (coarsenable, 8 <= N <= kMaxGrid,
// model/run_options.h). "" when n is accepted, else "got N; accepted: ..." for a message.
std::string check_verify_grid(int n);

// epsilon_m = h m / (4 sqrt2 atanh(0.9)): the interface spans about m cells from 0.1 to 0.9.
double epsilon_for_cells(int m, int n);

// Section 4.1: phi(x) = 0.5 + 0.01 rand(x) (constant in y and z) evolved with epsilon_m,
// dt = 0.05, to t = 10; the measured width in cells of every 0.1 -> 0.9 transition. For
// phi = (1 + tanh(x / (2 sqrt2 eps))) / 2 that width is 4 sqrt2 eps atanh(0.8), i.e. 0.746 m
// cells for epsilon_m; the formula's atanh(0.9) is the 0.05 -> 0.95 width (the paper's c in
// [-1, 1] from -0.9 to 0.9), which is m cells.
struct TransitionLayerResult {
  int m = 0;
  int n = 0;
  double epsilon = 0.0;
  int crossings = 0;   // phi = 1/2 crossings along the line
  int interfaces = 0;  // of which formed (reach 0.1 and 0.9 before the next crossing)
  double mean_width_cells = 0.0;
  double min_width_cells = 0.0;
  double max_width_cells = 0.0;
  double mean_width_cells_05 = 0.0;  // between phi = 0.05 and 0.95
  RunResult run;
};
TransitionLayerResult verify_transition_layer(int m, int n, double t_end, std::uint64_t seed,
                                              const ProgressFn& progress = {});

// Section 4.2: the cube 0.25 <= x,y,z <= 0.75 on n^3 (the paper: 64^3, epsilon = 0.015),
// dt = h, relaxed until ||dphi|| <= tol or max_steps. Sphericity pi^(1/3) (6V)^(2/3) / A (1 for a
// ball, 0.806 for a cube) with V the sharp volume of {phi > 1/2} (not the mass: the ball loses part
// of its mass to the surrounding phase) and A the area measure, and the ratio of the phi = 1/2
// radius along the axes to the radius along the cube diagonals (0.577 for the cube, 1 for a
// sphere).
struct CubeToSphereResult {
  double sphericity_initial = 0.0;
  double sphericity_final = 0.0;
  double radius_ratio_initial = 0.0;
  double radius_ratio_final = 0.0;
  double mean_radius_final = 0.0;
  RunResult run;
};
CubeToSphereResult verify_cube_to_sphere(int n, double epsilon, int max_steps, double tol,
                                         const ProgressFn& progress = {});
// Radius of the ball with the cube's volume 1/8: 0.3102.
double cube_sphere_radius();

// Radius of the phi = 1/2 level along a ray from the cell centre (0.5, 0.5, 0.5), by trilinear
// interpolation at sub-cell steps. Whole grids with a valid halo of at least 1.
double level_radius(const Field& phi, double dx, double dy, double dz);

// Section 4.3 / Table 1: sphere r = 0.25, epsilon = 0.0073 * 64 / N, dt = h, stop
// ||dphi|| <= 1e-5. area and total_mean_curvature are the diffuse measures of Appendix B
// (measure/measures.h area() and mean_curvature()), as in the paper's Table 1.
struct SphereConvergenceRow {
  int n = 0;
  double epsilon = 0.0;
  double area = 0.0;
  double total_mean_curvature = 0.0;
  double mean_curvature_mu = 0.0;
  int steps = 0;
  bool converged = false;  // the stop rule was met before max_steps
  double wall_seconds = 0.0;
};
SphereConvergenceRow verify_sphere(int n, double tol, int max_steps,
                                   const ProgressFn& progress = {});

// Table 1 as printed in the paper (N = 32, 64, 128, 256).
struct Table1Reference {
  int n = 0;
  double area = 0.0;
  double total_mean_curvature = 0.0;
};
const std::vector<Table1Reference>& table1_reference();

// One pass/fail check of a verification experiment: the measured value must lie in [lo, hi]
// (a NaN fails). expected is the reference printed beside it (the paper's number or the
// theoretical value); basis says in a few words where the range comes from.
struct VerifyCheck {
  std::string name;
  double value = 0.0;
  double expected = 0.0;
  double lo = 0.0;
  double hi = 0.0;
  std::string basis;
  bool passed() const { return value >= lo && value <= hi; }
};

// The checks of each experiment (docs/verification.md gives the measured values and why each
// range is what it is). table1_checks takes the rows in increasing N, each with its paper row.
std::vector<VerifyCheck> transition_checks(const TransitionLayerResult& r);
std::vector<VerifyCheck> cube_checks(const CubeToSphereResult& r, int max_steps);
std::vector<VerifyCheck> table1_checks(const std::vector<SphereConvergenceRow>& rows);

}  // namespace cmcsurf
