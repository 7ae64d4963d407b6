// Sweeps across nodes (docs/scaling.md, "Sweeps across nodes"): under mpirun the processes form
// groups of equal size (Decomposition::split), each group runs its share of a sweep's members as
// decomposed runs, and world rank 0 gathers the rows. This file holds the plan (how many groups,
// which members each runs) and what a group hands to world rank 0; the command is
// apps/cmd_sweep.cpp.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/preview.h"
#include "pipeline/sweep.h"

namespace cmcsurf {

// The units the members are dealt out in, in sweep order, each a list of member indices (as
// run_sweep numbers them: surfaces outermost): one member each, or with continuation one family
// (a surface's members start each from the one before, so one group runs them in order).
std::vector<std::vector<int>> sweep_units(const SweepParams& params);

// The group of each member, by member index: the units, largest first (most members; ties in
// sweep order), each to the group with the fewest members so far (ties: the lowest group). The
// members of one grid cost alike, so this is the longest-processing-time rule on member counts;
// for units of one member it deals them round robin.
std::vector<int> assign_members(const SweepParams& params, int groups);

// The default number of groups for `ranks` processes and `units` units, among the divisors G of
// `ranks` whose groups of ranks / G processes split the grid (`splits`): the largest G <= units
// sets the rounds, ceil(units / G); the smallest G with as few rounds is taken (fewer, larger
// groups finish each member sooner). If no such G <= units splits the grid, the smallest G that
// does (some groups then run nothing). G = ranks (groups of one) always splits.
int default_groups(int ranks, int units, const std::function<bool(int group_ranks)>& splits);

// Why `group_ranks` processes cannot run a member of `p` as `cmcsurf run` would under mpirun
// (the grid and every coarse level must split, the smoother must be red-black), naming the
// option; "" when they can (always for one process).
std::string group_grid_problem(const RunParams& p, int group_ranks);

// What a group's rank 0 hands to world rank 0 when the group is done.
struct GroupRows {
  struct Row {
    int index = 0;          // the member's index in the sweep
    nlohmann::json report;  // its report.json
    std::optional<GalleryMember> tile;  // its gallery.png tile (none with --no-preview)
  };
  int status = 0;        // the group's exit code (0: every member of it done)
  std::string message;   // why it stopped early, for world rank 0 to print ("" if printed)
  int kept = 0;          // sweep --resume: members found complete
  int resumed = 0;       // sweep --resume: members continued from their checkpoint
  std::vector<Row> rows;  // in the order the group ran them
};
// Bytes for gather_world_bytes (MessagePack: every double exact), and back; unpack throws
// std::runtime_error on bytes it cannot read.
std::string pack_group_rows(const GroupRows& rows);
GroupRows unpack_group_rows(const std::string& bytes);

}  // namespace cmcsurf
