// From what a user asked for to a validated RunParams: the names of the enumerations, what
// --fast selects and every range check, with the messages the command line prints (they name
// the option and what is accepted). Shared by apps/ (cmcsurf run, sweep) and python/.
#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

#include "model/run.h"

namespace cmcsurf {

// A user's option out of range; the message names the option ("--grid: got 50; ...").
struct OptionError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// What a user gave beside RunParams' own members (model/run_schema.h): the names of the
// choice options, converted and checked by finish_run_params, and which options were given
// (--fast leaves those alone). Keyed by the option's key.
struct RunChoices {
  std::map<std::string, std::string> text;
  std::set<std::string> given;
};

// --grid's upper bound (the verify experiments' grids share it).
constexpr int kMaxGrid = 2048;

// What --fast selects (docs/performance.md): N/2^K continuation with K <= 2 and N/2^K >= 32,
// V-cycles to 1e-2 of each step's change, extrapolated guesses, dt growing to 8 h (a grid
// continued from a coarser one starting there), the finest grid's V-cycles to 1e-1, and each
// relaxation ended at an equilibrium residual of fast_equilibrium_tol(N): 1e-3 at 128^3,
// scaled with h^2 like the grid's own spread of the local H, so that the residual adds about
// 5 % to it at any grid (docs/method.md, "The equilibrium stop rule").
constexpr double kFastMgRtol = 1e-2;
constexpr double kFastDtMaxFactor = 8.0;
// A continued grid's first step at the largest dt (--continued-dt-factor): with the coarser
// grids ended on their own equilibrium rule, skipping the ramp took 6-35 % fewer finest
// V-cycles in all 12 runs of P, D, G at 0.3 and 0.5 at 128^3 and 256^3 (docs/performance.md).
constexpr double kFastContinuedDtFactor = kFastDtMaxFactor;
constexpr double kFastMgRtolFinest = 0.1;
constexpr double kFastEquilibriumTol = 1e-3;  // at kFastEquilibriumGrid
constexpr int kFastEquilibriumGrid = 128;
// Anderson mixing of the last 3 steps once dt is at its largest (depths 2-6 all took 13-14
// finest steps for G at 0.5, 128^3, against 41 without; 3 costs 40 bytes per cell).
constexpr int kFastAndersonDepth = 3;
inline double fast_equilibrium_tol(int grid) {
  const double r = double(kFastEquilibriumGrid) / grid;
  return kFastEquilibriumTol * r * r;
}
int fast_coarse_levels(int grid);

// --paper's grid: the default before the fast mode was (epsilon 0.01 = 0.64 h).
constexpr int kPaperGrid = 64;

// Applies --paper (p.paper: fast off, kPaperGrid unless --grid was given) or --fast (p.fast,
// the default) where not given, converts the choices' names and checks every range (the
// surface and the volume fraction too when check_surface); throws OptionError.
void finish_run_params(RunParams& p, const RunChoices& c, bool check_surface);
// The range checks alone (those of finish_run_params, plus the parameters the command line
// does not set): for parameters read back from a checkpoint or sweep.json. Throws OptionError.
void check_run_params(const RunParams& p, bool check_surface);
// Why alpha cannot be a volume fraction on an N^3 grid ("" when it can): each phase needs at
// least one cell, or no surface is left to relax.
std::string check_fraction_on_grid(double alpha, int grid);

// The peak resident memory of a run's whole command on each of `ranks` processes, from the
// measured model of docs/performance.md ("Memory"): 112 bytes per cell with --extrapolate's two
// extra fields, 96 without, plus 64 MB for the process itself.
std::uint64_t estimate_run_bytes(const RunParams& p, int ranks = 1);
// "" when that estimate fits the memory this process may still take (parallel/memory.h);
// otherwise why not, naming --grid, both figures, the limit and the largest grid that fits.
std::string check_run_memory(const RunParams& p, int ranks = 1);

}  // namespace cmcsurf
