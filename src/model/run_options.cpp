#include "model/run_options.h"

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <variant>

#include <fmt/format.h>

#include "multigrid/fas.h"
#include "parallel/memory.h"
#include "model/run_schema.h"
#include "model/cell_geometry.h"
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

void finish_run_params(RunParams& p, const RunChoices& c, bool check_surface) {
  if (p.paper) {
    if (p.fast && c.given.count("fast") > 0)
      throw OptionError("--paper: not with --fast (the paper-faithful algorithm is the one "
                        "without the fast mode); accepted: one of them");
    for (const RunOption& o : run_option_table())
      if (o.paper != nullptr && c.given.count(o.key) == 0) o.paper(p);
  }
  for (const RunOption& o : run_option_table()) {
    if (p.fast && o.fast != nullptr && c.given.count(o.key) == 0) o.fast(p, check_surface);
  }
  for (const RunOption& o : run_option_table()) {
    const auto text = c.text.find(o.key);
    if (text != c.text.end() && !set_run_choice(o, p, text->second))
      throw OptionError(fmt::format("{}: got '{}'; accepted: {}", o.name(), text->second,
                                    run_choice_names(o)));
  }
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
    // A double structure is the |F| > c of a nodal formula.
    if (p.structure == Structure::kDouble && !is_nodal_surface(p.surface))
      throw OptionError(fmt::format("--structure: got double for --surface {}; accepted: single "
                                    "(a double structure is made from a nodal formula: P, D, "
                                    "G, ..., expr:)",
                                    p.surface));
  }
  // The bound first: the sizes m 2^k that coarsenable suggests are of no use beyond it.
  require(p.grid <= kMaxGrid, "--grid", p.grid, fmt::format("N <= {}", kMaxGrid).c_str());
  const std::string grid_problem = check_coarsenable(p.grid);  // after the bound: no overflow
  if (!grid_problem.empty()) throw OptionError("--grid: " + grid_problem);
  if (const std::string why = check_fraction_on_grid(p.volume_fraction, p.grid);
      check_surface && !why.empty())
    throw OptionError("--volume-fraction: " + why);
  // Each option's own range (model/run_schema.h), in the table's order.
  for (const RunOption& o : run_option_table()) {
    if (*o.accepted == '\0') continue;
    std::visit(
        [&](const auto& v) {
          using T = std::decay_t<decltype(v)>;
          if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>)
            require(o.range.contains(double(v)), o.name().c_str(), v, o.accepted);
        },
        run_option_value(o, p));
  }
  // The ranges that depend on other options.
  if (p.coarse_levels > 0 && !check_coarsenable(p.grid >> p.coarse_levels).empty())
    throw OptionError(fmt::format("--coarse-levels: {} halvings of --grid {} give {}, which {}",
                                  p.coarse_levels, p.grid, p.grid >> p.coarse_levels,
                                  check_coarsenable(p.grid >> p.coarse_levels)));
  require(p.dt_max_factor == 0.0 || (p.dt_max_factor >= p.dt_factor && p.dt_max_factor <= 1000.0),
          "--dt-max-factor", p.dt_max_factor, "0 (fixed dt) or --dt-factor <= F <= 1000");
  require(p.solver.fas.pre_sweeps + p.solver.fas.post_sweeps >= 1, "--pre-sweeps/--post-sweeps",
          p.solver.fas.pre_sweeps + p.solver.fas.post_sweeps, "at least one sweep in total");
  try {
    parse_parallel_distances(p.parallel_distances);
  } catch (const std::invalid_argument& e) {
    throw OptionError(fmt::format("--parallel-distances: {}", e.what()));
  }
  // The lipid relation needs both numbers.
  require(p.lipid_length == 0.0 || p.lipid_fraction > 0.0, "--lipid-fraction", p.lipid_fraction,
          "0 < F < 1 with --lipid-length");
  require(p.lipid_fraction == 0.0 || p.lipid_length > 0.0, "--lipid-length", p.lipid_length,
          "L > 0 (nm) with --lipid-fraction");
}

}  // namespace cmcsurf
