// Design from targets (docs/scaffolds.md, "Design from targets"): a scaffold's free parameters
// solved from what a designer states. --target-modulus (GPa, with --material) and
// --target-permeability (m^2) fix the porosity (a network's member, or a sheet's wall) from
// the unit cell's computed properties; the permeability, which scales with the cell size
// squared, fixes the cell size instead when the porosity is given or solved by the modulus;
// --pore-size fixes the cell size from the mean pore diameter (linear in it); --min-wall is a
// constraint on the wall's 5th percentile. Everything is computed here; `scaffold` only
// parses, supplies the members (its cache) and prints.
#pragma once

#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "grid/field.h"
#include "mesh/scaffold.h"
#include "mesh/scaffold_part.h"
#include "pipeline/properties_stage.h"

namespace cmcsurf {

// A value V or a ramp A:B along the part's axis (graded), each a positive number; "" is none.
struct TargetValue {
  double from = NAN, to = NAN;
  bool given() const { return !std::isnan(from); }
  bool ramp() const { return given() && from != to; }
};
// option names the value in the error (std::invalid_argument): "--target-modulus: got ...".
TargetValue parse_target_value(const std::string& text, const std::string& option);

struct DesignTargets {
  double modulus_gpa = NAN;      // --target-modulus: mean of the cell's E_x, E_y, E_z
  double permeability_m2 = NAN;  // --target-permeability: mean of the cell's k_xx, k_yy, k_zz
  double pore_size = NAN;        // --pore-size: mean pore diameter (morphometry), output units
  double min_wall = NAN;         // --min-wall: the wall's 5th percentile, output units
  bool strict_min_wall = false;  // --strict-min-wall: refuse instead of warning
};

// The property a target names.
enum class TargetQuantity { kModulus, kPermeability };
const char* target_option(TargetQuantity q);  // "--target-modulus", "--target-permeability"

// The porosities a design searches for each solid: networks whose CMC members keep their
// family's topology and hold their struts at 32^3, sheets whose walls are 2 voxels or more at
// 32^3 and thinner than half a cell.
inline constexpr double kNetworkPorosityMin = 0.3, kNetworkPorosityMax = 0.85;
inline constexpr double kSheetPorosityMin = 0.5, kSheetPorosityMax = 0.9;
std::pair<double, double> design_porosity_range(SolidKind solid);

// The problem as the user states it. `porosity` NaN: solved by the modulus (else the
// permeability); `cell_size_given` false lets the permeability or the pore size solve it.
struct DesignProblem {
  DesignTargets targets;
  ScaffoldDesign design;         // solid, cell size (the start when solved), units
  bool porosity_given = true;    // design.porosity is the user's
  bool cell_size_given = false;  // --cell-size was typed
  PropertiesRequest material;    // youngs_modulus_gpa, poisson_ratio, tolerance
  // The solve stops within this of the target: CMC members computed with --fast scatter by
  // about 1 % in modulus from one porosity to the next (G at 32^3: 8.22, 8.13, 8.10, 7.61 GPa at
  // porosity 0.6970, 0.6986, 0.6993, 0.7015), so a tighter stop only costs members.
  double rel_tol = 0.02;
  int max_evaluations = 8;       // property evaluations per solved parameter
};

// What solves what, or std::invalid_argument naming the options and what is accepted (exit 2
// material): a missing --material or physical --units, two targets for one parameter, a
// modulus above the Hashin-Shtrikman bound at the range's densest porosity.
struct DesignPlan {
  bool solve_porosity = false;
  TargetQuantity porosity_by = TargetQuantity::kModulus;
  bool cell_size_by_permeability = false;
  bool cell_size_by_pore_size = false;
  bool any() const {
    return solve_porosity || cell_size_by_permeability || cell_size_by_pore_size;
  }
};
DesignPlan plan_design(const DesignProblem& p);

// No member of the family meets a target: the message names the reachable range (exit 1).
struct TargetUnreachable : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A 1D solve of f(x) = target for a positive, monotone f on [lo, hi], in log f: a first step
// from x0 with the guessed slope d log f / dx (its sign says whether f increases), then secant
// steps kept inside the bracket the evaluations make (bisection when a step leaves it). A step
// past an end of the range evaluates that end; a target beyond it evaluates the other end too
// and leaves `reached` false with both ends' values (the reachable range).
struct MonotoneSolve {
  double x = NAN, value = NAN;  // the evaluation closest to the target (in log)
  bool reached = false;         // |value / target - 1| <= rel_tol
  std::vector<std::pair<double, double>> evaluations;  // (x, f(x)) in order
  double value_at_lo = NAN, value_at_hi = NAN;         // when not reached
};
MonotoneSolve solve_monotone(const std::function<double(double)>& f, double target, double lo,
                             double hi, double x0, double slope_guess, double rel_tol,
                             int max_evaluations);

// The targeted quantity of a design's unit cell (mean of x, y, z in GPa or m^2): phi's phase 1
// (a network), or the wall around phi's surface of the given porosity or thickness (a sheet;
// thickness in output units). base: material, cell size, units, tolerance.
double cell_quantity(const Field& phi, TargetQuantity q, SolidKind solid, double porosity,
                     double thickness, const PropertiesRequest& base);

// The member whose unit cell has this porosity: a network's CMC member at volume fraction
// 1 - porosity (computed or cached by the caller), a sheet's balanced one.
using MemberAt = std::function<Field(double porosity)>;

struct DesignSolution {
  double porosity = NAN, cell_size = NAN;
  nlohmann::json report;  // targets, solved, evaluations, seconds (FILE.json's design keys)
};
// Solves the plan's parameters for one target value set (a graded target: once per end).
// Throws TargetUnreachable naming the reachable range. progress: a line per evaluation.
DesignSolution solve_design(const DesignProblem& p, const DesignPlan& plan,
                            const MemberAt& member,
                            const std::function<void(const std::string&)>& progress = {});

// The targets recomputed on the part as written (phi: its member; report: design_scaffold's):
// its cell's modulus and permeability, its mean pore size and wall 5th percentile, each with
// the relative error ("achieved"); warnings (or, strict, a TargetUnreachable) for --min-wall.
nlohmann::json confirm_design(const DesignProblem& p, const Field& phi,
                              const nlohmann::json& part_report,
                              std::vector<std::string>& warnings);

}  // namespace cmcsurf
