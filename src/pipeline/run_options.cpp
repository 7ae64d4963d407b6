#include "pipeline/run_options.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "multigrid/fas.h"
#include "parallel/memory.h"
#include "surfaces/initial.h"

namespace cmcsurf {

namespace {

template <class T>
void require(bool ok, const char* option, T value, const char* accepted) {
  if (!ok) throw OptionError(fmt::format("{}: got {}; accepted: {}", option, value, accepted));
}

}  // namespace

int fast_coarse_levels(int grid) {
  int k = 0;
  while (k < 2 && (grid >> (k + 1)) >= 32 && check_coarsenable(grid >> (k + 1)).empty()) ++k;
  return k;
}

void finish_run_params(RunParams& p, const RunChoices& s, bool check_surface) {
  if (s.fast) {
    p.fast = true;
    if (!s.mg_rtol_given) p.solver.rtol = kFastMgRtol;
    if (!s.dt_max_factor_given) p.dt_max_factor = kFastDtMaxFactor;
    if (!s.extrapolate_given) p.solver.extrapolate = true;
    if (!s.settle_tol_given) p.settle_tol = kFastSettleTol;
    if (!s.mg_rtol_finest_given) p.mg_rtol_finest = kFastMgRtolFinest;
    if (!s.coarse_levels_given && check_coarsenable(p.grid).empty() &&
        (!check_surface || is_nodal_surface(p.surface)))
      p.coarse_levels = fast_coarse_levels(p.grid);
  }
  if (s.stop == "area")
    p.stop = StopRule::kArea;
  else if (s.stop == "phi")
    p.stop = StopRule::kPhi;
  else
    throw OptionError(fmt::format("--stop: got '{}'; accepted: area, phi", s.stop));
  if (s.smoother == "redblack")
    p.smoother = SweepOrder::kRedBlack;
  else if (s.smoother == "lex")
    p.smoother = SweepOrder::kLexicographic;
  else
    throw OptionError(fmt::format("--smoother: got '{}'; accepted: redblack, lex", s.smoother));
  if (s.constrain == "volume")
    p.constrain = Constraint::kVolume;
  else if (s.constrain == "mass")
    p.constrain = Constraint::kMass;
  else
    throw OptionError(fmt::format("--constrain: got '{}'; accepted: volume, mass", s.constrain));

  check_run_params(p, check_surface);
}

std::string check_fraction_on_grid(double alpha, int grid) {
  const double cells = double(grid) * grid * grid;
  if (alpha * cells >= 1.0 && (1.0 - alpha) * cells >= 1.0) return {};
  return fmt::format("got {} at --grid {}; accepted: 1/N^3 <= A <= 1 - 1/N^3 (at least one "
                     "cell of each phase; {:.3g} to {:.9g} here)",
                     alpha, grid, 1.0 / cells, 1.0 - 1.0 / cells);
}

std::uint64_t estimate_run_bytes(const RunParams& p, int ranks) {
  const double cells = double(p.grid) * p.grid * p.grid / std::max(ranks, 1);
  const double per_cell = p.solver.extrapolate ? 112.0 : 96.0;
  return std::uint64_t(cells * per_cell) + (std::uint64_t(64) << 20);
}

std::string check_run_memory(const RunParams& p, int ranks) {
  const MemoryHeadroom room = memory_headroom();
  const std::uint64_t need = estimate_run_bytes(p, ranks);
  if (need <= room.bytes) return {};
  int fits = 0;
  for (int n = p.grid - 1; n >= 8 && fits == 0; --n) {
    RunParams q = p;
    q.grid = n;
    if (check_coarsenable(n).empty() && estimate_run_bytes(q, ranks) <= room.bytes) fits = n;
  }
  return fmt::format("--grid {}: the run needs about {}{} but this process may take only {} "
                     "more ({}); {}",
                     p.grid, format_bytes(need), ranks > 1 ? " per process" : "",
                     format_bytes(room.bytes), room.source,
                     fits > 0 ? fmt::format("--grid {} fits", fits)
                              : std::string("not even --grid 8 fits"));
}

void check_run_params(const RunParams& p, bool check_surface) {
  if (check_surface) {
    try {
      validate_surface(p.surface);
    } catch (const std::invalid_argument& e) {
      throw OptionError(fmt::format("--surface: {}", e.what()));
    }
    require(p.volume_fraction > 0.0 && p.volume_fraction < 1.0, "--volume-fraction",
            p.volume_fraction, "0 < A < 1");
    // The continuation coarsens the nodal formula; sphere, cube and noise have none to coarsen.
    if (p.coarse_levels > 0 && !is_nodal_surface(p.surface))
      throw OptionError(fmt::format("--coarse-levels: got {} for --surface {}; accepted: 0 (the "
                                    "coarse-to-fine continuation starts from a nodal formula)",
                                    p.coarse_levels, p.surface));
  }
  // The bound first: the sizes m 2^k that coarsenable suggests are of no use beyond it.
  require(p.grid <= kMaxGrid, "--grid", p.grid, fmt::format("N <= {}", kMaxGrid).c_str());
  const std::string grid_problem = check_coarsenable(p.grid);  // after the bound: no overflow
  if (!grid_problem.empty()) throw OptionError("--grid: " + grid_problem);
  if (const std::string why = check_fraction_on_grid(p.volume_fraction, p.grid);
      check_surface && !why.empty())
    throw OptionError("--volume-fraction: " + why);
  require(p.epsilon > 0.0 && p.epsilon < 1.0, "--epsilon", p.epsilon, "0 < E < 1");
  require(p.dt_factor > 0.0 && std::isfinite(p.dt_factor), "--dt-factor", p.dt_factor,
          "C > 0 (dt = C h)");
  require(p.tol > 0.0 && std::isfinite(p.tol), "--tol", p.tol, "T > 0");
  require(p.max_steps >= 1, "--max-steps", p.max_steps, "K >= 1");
  require(p.radius > 0.0 && p.radius < 0.5, "--radius", p.radius, "0 < R < 0.5");
  require(p.solver.tol > 0.0 && std::isfinite(p.solver.tol), "--mg-tol", p.solver.tol, "> 0");
  require(p.solver.rtol >= 0.0 && p.solver.rtol < 1.0, "--mg-rtol", p.solver.rtol, "0 <= R < 1");
  require(p.coarse_levels >= 0 && p.coarse_levels <= 4, "--coarse-levels", p.coarse_levels,
          "0..4");
  if (p.coarse_levels > 0 && !check_coarsenable(p.grid >> p.coarse_levels).empty())
    throw OptionError(fmt::format("--coarse-levels: {} halvings of --grid {} give {}, which {}",
                                  p.coarse_levels, p.grid, p.grid >> p.coarse_levels,
                                  check_coarsenable(p.grid >> p.coarse_levels)));
  require(p.dt_max_factor == 0.0 || (p.dt_max_factor >= p.dt_factor && p.dt_max_factor <= 1000.0),
          "--dt-max-factor", p.dt_max_factor, "0 (fixed dt) or --dt-factor <= F <= 1000");
  require(p.mg_rtol_finest >= 0.0 && p.mg_rtol_finest < 1.0, "--mg-rtol-finest",
          p.mg_rtol_finest, "0 (as --mg-rtol) <= R < 1");
  require(p.settle_tol >= 0.0 && p.settle_tol < 1.0, "--settle-tol", p.settle_tol,
          "0 (off) <= T < 1");
  require(p.solver.max_vcycles >= 1, "--max-vcycles", p.solver.max_vcycles, ">= 1");
  require(p.solver.fas.pre_sweeps >= 0 && p.solver.fas.pre_sweeps <= 50, "--pre-sweeps",
          p.solver.fas.pre_sweeps, "0..50");
  require(p.solver.fas.post_sweeps >= 0 && p.solver.fas.post_sweeps <= 50, "--post-sweeps",
          p.solver.fas.post_sweeps, "0..50");
  require(p.solver.fas.pre_sweeps + p.solver.fas.post_sweeps >= 1, "--pre-sweeps/--post-sweeps",
          p.solver.fas.pre_sweeps + p.solver.fas.post_sweeps, "at least one sweep in total");
  require(p.prerelax_steps >= 0, "--prerelax-steps", p.prerelax_steps, ">= 0");
  require(p.prerelax_epsilon_factor > 0.0 && p.prerelax_epsilon_factor <= 1000.0,
          "--prerelax-epsilon-factor", p.prerelax_epsilon_factor, "0 < F <= 1000");
  require(p.bisection_tol > 0.0 && std::isfinite(p.bisection_tol), "--bisection-tol",
          p.bisection_tol, "> 0");
  require(p.bisection_max_it >= 1, "--bisection-max-it", p.bisection_max_it, ">= 1");
  require(p.volume_tol > 0.0 && p.volume_tol < 0.1, "--volume-tol", p.volume_tol, "0 < T < 0.1");
  require(p.max_volume_corrections >= 0 && p.max_volume_corrections <= 100,
          "--max-volume-corrections", p.max_volume_corrections, "0..100");
  // Not options of the command line, but parameters a checkpoint or sweep.json carries.
  require(std::isfinite(p.noise_amplitude) && p.noise_amplitude >= 0.0, "noise_amplitude",
          p.noise_amplitude, "finite, >= 0");
  require(p.solver.fas.coarsest_max_sweeps >= 1, "coarsest_max_sweeps",
          p.solver.fas.coarsest_max_sweeps, ">= 1");
  require(p.solver.fas.coarsest_reduction > 0.0 && p.solver.fas.coarsest_reduction < 1.0,
          "coarsest_reduction", p.solver.fas.coarsest_reduction, "0 < R < 1");
}

}  // namespace cmcsurf
