// Families computed apart, in one sweep folder (`cmcsurf merge`, docs/families.md): the
// members of complete sweeps with the same run parameters copied into a new folder with one
// sweep.csv, sweep.json, families.png (and gallery.png, report.html) as if one sweep had
// computed them all. The merged sweep is a sweep like any other: its members are the
// surfaces times the volume fractions of the sources (in the order they first appear), each
// from exactly one source, so `sweep --resume` on it keeps them all.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/sweep.h"

namespace cmcsurf {

struct MergeOptions {
  bool figures = true;   // families.png/.svg (--no-plot: false)
  bool diffuse = false;  // families.png: the diffuse layer's values too
  bool page = true;      // report.html, gallery.png where the sources drew previews
};

// The merged sweep of the sources' sweep.json files (read and checked as `sweep --resume`
// reads them): the same parameters and continuation, no expr: surfaces (they are named by
// their position), every member of surfaces x fractions in exactly one source; with
// continuation each family from one source, with the same fractions. Throws OptionError
// naming the source and the difference. `origin[i]`: the source of member i.
struct MergePlan {
  SweepParams sweep;
  nlohmann::json outputs;           // the first source's output options
  std::vector<std::size_t> origin;  // per member (surfaces outermost): index into sources
};
MergePlan plan_merge(const std::vector<std::filesystem::path>& sources);

// Writes the merged folder into `out` (claimed by the caller, not one of the sources): each
// member's folder copied, then sweep.csv, the figures, sweep.json ("merged_from": the sources)
// and the page. Returns sweep.json.
nlohmann::json write_merged_sweep(const std::vector<std::filesystem::path>& sources,
                                  const MergePlan& plan, const std::filesystem::path& out,
                                  const MergeOptions& options);

}  // namespace cmcsurf
